// Checks what the independent Fast DDS peer received from aerograsp against
// Foxglove's ROS 2 CDR decoder (@foxglove/rosmsg2-serialization) fed with the
// ROS 2 Humble message definitions (@foxglove/rosmsg-msgs-common):
//   - every message starts with the CDR little-endian encapsulation header;
//   - topics of one latched message (keep last 1, as /tf_static) are checked on
//     their last message only: a newer one may replace an older in flight;
//   - Foxglove's decoder and Fast DDS's dynamic types read the same fields;
//   - each topic carries, in order, what aerograsp was asked to publish
//     (EXPECTED, written by ros2_publish_tool), every field equal; a pose's
//     quaternion stands for the rotation matrix it was made from;
//   - every topic was received.
// Usage: node crosscheck.js RECEIVED.jsonl EXPECTED.json
"use strict";
const fs = require("fs");
const { MessageReader } = require("@foxglove/rosmsg2-serialization");
const definitions = require("@foxglove/rosmsg-msgs-common").ros2humble;

const [receivedPath, expectedPath] = process.argv.slice(2);
const received = fs.readFileSync(receivedPath, "utf8").split("\n").filter((l) => l.length > 0).map((l) => JSON.parse(l));
const expected = JSON.parse(fs.readFileSync(expectedPath, "utf8"));

let failures = 0;
let checks = 0;
function fail(message) {
  failures += 1;
  console.error("FAIL: " + message);
}

/// The root definition of a ROS 2 type ("pkg/msg/Name") and every one it uses.
function definitionsOf(rosType) {
  const out = [];
  const seen = new Set();
  const visit = (name) => {
    if (seen.has(name)) return;
    seen.add(name);
    const d = definitions[name];
    if (!d) throw new Error(`no ROS 2 definition of ${name}`);
    out.push(d);
    for (const field of d.definitions) if (field.isComplex) visit(field.type);
  };
  visit(rosType.replace("/msg/", "/"));
  return out;
}

function plain(value) {
  if (ArrayBuffer.isView(value)) return Array.from(value);
  if (Array.isArray(value)) return value.map(plain);
  if (value !== null && typeof value === "object") {
    const o = {};
    for (const [k, v] of Object.entries(value)) o[k] = plain(v);
    return o;
  }
  return value;
}

/// Field-by-field equality; returns the first difference's path, or null.
function difference(a, b, path) {
  if (typeof a === "boolean" || typeof b === "boolean") return a === b ? null : `${path}: ${a} != ${b}`;
  if (typeof a === "number" && typeof b === "number") return a === b ? null : `${path}: ${a} != ${b}`;
  if (typeof a === "string" || typeof b === "string") return a === b ? null : `${path}: '${a}' != '${b}'`;
  if (Array.isArray(a) && Array.isArray(b)) {
    if (a.length !== b.length) return `${path}: ${a.length} items != ${b.length}`;
    for (let i = 0; i < a.length; ++i) {
      const d = difference(a[i], b[i], `${path}[${i}]`);
      if (d) return d;
    }
    return null;
  }
  if (a && b && typeof a === "object" && typeof b === "object") {
    const keys = new Set([...Object.keys(a), ...Object.keys(b)].filter((k) => k !== "__matrix"));
    for (const k of keys) {
      if (!(k in a)) return `${path}.${k}: missing on the left`;
      if (!(k in b)) return `${path}.${k}: missing on the right`;
      const d = difference(a[k], b[k], `${path}.${k}`);
      if (d) return d;
    }
    return null;
  }
  return `${path}: ${JSON.stringify(a)} != ${JSON.stringify(b)}`;
}

/// Every {translation|position, rotation|orientation, __matrix} below `value`:
/// the quaternion's rotation and the translation equal the matrix's.
function checkMatrices(value, path) {
  if (!value || typeof value !== "object") return;
  if (value.__matrix) {
    const m = value.__matrix;
    const t = value.translation || value.position;
    const q = value.rotation || value.orientation;
    const { x, y, z, w } = q;
    const r = [
      [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
      [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
      [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ];
    checks += 1;
    for (let i = 0; i < 3; ++i) {
      for (let j = 0; j < 3; ++j) {
        if (Math.abs(r[i][j] - m[4 * i + j]) > 1e-12) fail(`${path}: rotation[${i}][${j}] ${r[i][j]} != ${m[4 * i + j]}`);
      }
    }
    if (t.x !== m[3] || t.y !== m[7] || t.z !== m[11]) fail(`${path}: translation differs from the matrix`);
    return;
  }
  for (const [k, v] of Object.entries(value)) checkMatrices(v, `${path}.${k}`);
}

const readers = new Map();
const byTopic = new Map();
for (const message of received) {
  if (!readers.has(message.type)) readers.set(message.type, new MessageReader(definitionsOf(message.type)));
  const bytes = Uint8Array.from(Buffer.from(message.cdr, "hex"));
  checks += 1;
  // Encapsulation CDR_LE (0x0001); the options' low bits may count the end's padding (XTypes 1.3).
  if (bytes[0] !== 0x00 || bytes[1] !== 0x01) {
    fail(`${message.topic}: encapsulation ${Array.from(bytes.slice(0, 2))} is not CDR little-endian (0 1)`);
  }
  let decoded;
  try {
    decoded = plain(readers.get(message.type).readMessage(bytes));
  } catch (e) {
    fail(`${message.topic}: Foxglove's decoder cannot read the bytes: ${e.message}`);
    continue;
  }
  checks += 1;
  const d = difference(decoded, message.fields, message.topic);
  if (d) fail(`Foxglove's decoder and Fast DDS disagree: ${d}`);
  if (!byTopic.has(message.topic)) byTopic.set(message.topic, []);
  byTopic.get(message.topic).push(decoded);
}

const latestOnly = new Set(expected.__latest_only || []);
delete expected.__latest_only;
for (let [topic, messages] of Object.entries(expected)) {
  let got = byTopic.get(topic) || [];
  if (latestOnly.has(topic) && got.length > 0) {
    got = got.slice(-1);
    messages = messages.slice(-1);
  }
  checks += 1;
  if (got.length !== messages.length) {
    fail(`${topic}: ${got.length} messages received, ${messages.length} published`);
    continue;
  }
  messages.forEach((want, i) => {
    checks += 1;
    const d = difference(got[i], want, `${topic}#${i}`);
    if (d) fail(`what was published and what was received differ: ${d}`);
    checkMatrices(want, `${topic}#${i}`);
  });
}
for (const topic of [...Object.keys(expected), "/diagnostics"]) {
  if (!byTopic.has(topic)) fail(`${topic}: nothing received`);
}

for (const [topic, messages] of [...byTopic.entries()].sort()) console.log(`  ${topic}: ${messages.length} decoded`);
console.log(`${checks - failures} passed, ${failures} failed`);
process.exit(failures === 0 ? 0 : 1);
