// The independent side of the MAVLink 2 cross-check: node-mavlink (and the
// mavlink-mappings definitions it uses) against aerograsp's codec.
//   node crosscheck.js check FILE   decode the frames aerograsp wrote into FILE;
//                                   each must parse (CRC with CRC_EXTRA, signature
//                                   when signed) and give the listed field values
//   node crosscheck.js write FILE   write frames node-mavlink encodes (some signed,
//                                   some with extensions cut to zero) with their values
// A frame's "values" list its fields in wire order (the FIELDS order of
// mavlink-mappings), so the two sides also agree on the field layout.
'use strict';
const fs = require('fs');
const { Readable } = require('stream');
const {
  MavLinkPacketSplitter, MavLinkPacketParser, MavLinkProtocolV2, MavLinkPacketSignature,
} = require('node-mavlink');
const { minimal, common } = require('mavlink-mappings');

const REGISTRY = { ...minimal.REGISTRY, ...common.REGISTRY };
const MESSAGE_IDS = [0, 1, 30, 32, 76, 77, 84, 85, 245, 253];

function same(field, expected, actual) {
  if (expected === 'NaN') return Number.isNaN(actual);
  if (field.type.startsWith('char')) return String(actual).replace(/\0+$/, '') === expected;
  if (typeof actual === 'bigint') return actual === BigInt(expected);
  if (field.type === 'float') return Math.fround(expected) === actual;
  return expected === actual;
}

async function check(file) {
  const frames = JSON.parse(fs.readFileSync(file, 'utf8'));
  const packets = [];
  let crcErrors = 0;
  const splitter = new MavLinkPacketSplitter({}, { onCrcError: () => { crcErrors += 1; } });
  const stream = Readable.from(frames.map(f => Buffer.from(f.hex, 'hex'))).pipe(splitter).pipe(new MavLinkPacketParser());
  for await (const packet of stream) packets.push(packet);
  const failures = [];
  if (crcErrors) failures.push(`${crcErrors} CRC errors`);
  if (packets.length !== frames.length) failures.push(`${packets.length} packets parsed of ${frames.length} frames`);
  packets.forEach((packet, i) => {
    const frame = frames[i];
    const clazz = REGISTRY[packet.header.msgid];
    const where = `frame ${i} (${frame.name})`;
    if (!clazz || packet.header.msgid !== frame.msgid) {
      failures.push(`${where}: msgid ${packet.header.msgid}`);
      return;
    }
    for (const key of ['sysid', 'compid', 'seq']) {
      if (packet.header[key] !== frame[key]) failures.push(`${where}: header ${key} ${packet.header[key]} != ${frame[key]}`);
    }
    if (frame.signed) {
      const key = Buffer.from(frame.key, 'hex');
      if (!packet.signature || !packet.signature.matches(key)) failures.push(`${where}: signature does not verify`);
      else if (packet.signature.linkId !== frame.link_id || packet.signature.timestamp !== frame.timestamp) {
        failures.push(`${where}: signature link ${packet.signature.linkId} / timestamp ${packet.signature.timestamp}`);
      }
    }
    const data = packet.protocol.data(packet.payload, clazz);
    clazz.FIELDS.forEach((field, k) => {
      if (!same(field, frame.values[k], data[field.name])) {
        failures.push(`${where}: ${field.source} = ${data[field.name]}, aerograsp wrote ${frame.values[k]}`);
      }
    });
  });
  const covered = new Set(frames.map(f => f.name));
  console.log(`node-mavlink decoded ${packets.length} aerograsp frames (${covered.size} message types, ` +
              `${frames.filter(f => f.signed).length} signed)`);
  failures.forEach(f => console.error(`  MISMATCH ${f}`));
  return failures.length === 0;
}

// Deterministic field values of every type (seeded LCG, no Math.random).
function valueMaker(seed) {
  let state = seed >>> 0;
  const next = () => (state = (Math.imul(state, 1664525) + 1013904223) >>> 0);
  return field => {
    const r = next();
    switch (field.type) {
      case 'uint8_t': case 'uint8_t_mavlink_version': return r & 0xff;
      case 'int8_t': return (r & 0xff) - 128;
      case 'uint16_t': return r & 0xffff;
      case 'int16_t': return (r & 0xffff) - 32768;
      case 'uint32_t': return r;
      case 'int32_t': return r | 0;
      case 'float': return Math.fround((r / 0xffffffff - 0.5) * 2000);
      default:
        if (field.type.startsWith('char')) return `node-mavlink says ${r.toString(16)}`;
        throw new Error(`no value for ${field.type}`);
    }
  };
}

function write(file) {
  const key = Buffer.from('00112233445566778899aabbccddeeff00112233445566778899aabbccddeeff', 'hex');
  const protocol = new MavLinkProtocolV2(42, 191);
  // Signed frames carry the flag in the header (it is under the CRC), as sendSigned() does.
  const signing = new MavLinkProtocolV2(42, 191, MavLinkProtocolV2.IFLAG_SIGNED);
  const frames = [];
  let seq = 0;
  const emit = (id, values, { signed = false, cutExtensions = false } = {}) => {
    const clazz = REGISTRY[id];
    const message = new clazz();
    clazz.FIELDS.forEach((field, k) => {
      if (cutExtensions && field.extension) values[k] = field.type.startsWith('char') ? '' : 0;
      message[field.name] = values[k];
    });
    let buffer = (signed ? signing : protocol).serialize(message, seq);
    const frame = { name: clazz.MSG_NAME, msgid: id, sysid: 42, compid: 191, seq, signed };
    if (signed) {
      const timestamp_ms = Date.UTC(2026, 0, 1) + frames.length;  // growing
      buffer = signing.sign(buffer, 7, key, timestamp_ms);
      const signature = new MavLinkPacketSignature(buffer);
      Object.assign(frame, { key: key.toString('hex'), link_id: 7, timestamp: signature.timestamp });
    }
    frame.hex = buffer.toString('hex');
    frame.values = values;
    frames.push(frame);
    seq = (seq + 1) & 0xff;
  };
  MESSAGE_IDS.forEach((id, i) => {
    const make = valueMaker(1000 + i);
    const values = () => REGISTRY[id].FIELDS.map(make);
    emit(id, values());
    emit(id, values(), { signed: true });
    if (REGISTRY[id].FIELDS.some(f => f.extension)) emit(id, values(), { cutExtensions: true });
  });
  fs.writeFileSync(file, JSON.stringify(frames, null, 1));
  console.log(`node-mavlink wrote ${frames.length} frames (${MESSAGE_IDS.length} message types) to ${file}`);
  return true;
}

async function main() {
  const [command, file] = process.argv.slice(2);
  let ok;
  if (command === 'check') ok = await check(file);
  else if (command === 'write') ok = write(file);
  else {
    console.error('usage: node crosscheck.js check|write FILE');
    ok = false;
  }
  process.exit(ok ? 0 : 1);
}

main().catch(e => { console.error(e); process.exit(1); });
