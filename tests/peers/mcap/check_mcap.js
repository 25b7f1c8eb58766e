// The independent side of the MCAP check: @mcap/core reads aerograsp's MCAP
// files (CRCs validated) and @foxglove/rosmsg2-serialization decodes every
// message with the ROS 2 definitions the file carries.
//   node check_mcap.js check FILE [EXPECTED]
//       the indexed reader: footer, summary (its CRC), statistics, chunk and
//       message indexes; every message read through the indexes (chunk CRCs),
//       decoded without trailing bytes and counted per channel against the
//       statistics; a seek to the middle returns exactly the later messages;
//       the data section's CRC recomputed; the streaming reader agrees.
//       EXPECTED (JSON from mcap_check_tool): messages whose decoded fields must
//       equal the listed values.
//   node check_mcap.js partial FILE
//       a file cut short (a full disk): the streaming reader reads every record
//       up to the end without an error; each message decodes.
// Prints one JSON line: bytes, chunks, messages and per-topic counts.
'use strict';
const fs = require('fs');
const { crc32 } = require('@foxglove/crc');
const { McapIndexedReader, McapStreamReader } = require('@mcap/core');
const { parse } = require('@foxglove/rosmsg');
const { MessageReader } = require('@foxglove/rosmsg2-serialization');
const zstd = require('@foxglove/wasm-zstd');
const lz4 = require('@foxglove/wasm-lz4');

const decompressHandlers = {
  zstd: (buffer, size) => zstd.decompress(buffer, Number(size)),
  lz4: (buffer, size) => lz4(buffer, Number(size)),
};

function fail(message) {
  throw new Error(message);
}

// One MessageReader per schema, built from the file's own ros2msg text.
function decoderFor(schema, cache) {
  if (!cache.has(schema.id)) {
    if (schema.encoding !== 'ros2msg') fail(`schema ${schema.name}: encoding ${schema.encoding}`);
    const text = new TextDecoder().decode(schema.data);
    cache.set(schema.id, new MessageReader(parse(text, { ros2: true })));
  }
  return cache.get(schema.id);
}

function decode(reader, data, where) {
  const value = reader.readMessage(data);
  if (reader.lastReadHadTrailingBytes()) fail(`${where}: trailing bytes after the message`);
  return value;
}

// Expected values: numbers exactly (null for NaN), strings, arrays, objects;
// {"$bytes_length": N, "$bytes_crc32": C} for a byte array; {"$jpeg": true}
// for a byte array holding one JPEG (FFD8 ... FFD9).
function compare(expected, actual, path) {
  if (expected !== null && typeof expected === 'object' && '$jpeg' in expected) {
    const n = actual.length;
    if (!(actual instanceof Uint8Array) || n < 4 || actual[0] !== 0xff || actual[1] !== 0xd8 ||
        actual[n - 2] !== 0xff || actual[n - 1] !== 0xd9) {
      fail(`${path}: not a JPEG`);
    }
    return;
  }
  if (expected !== null && typeof expected === 'object' && '$bytes_length' in expected) {
    if (!(actual instanceof Uint8Array)) fail(`${path}: not a byte array`);
    if (actual.length !== expected.$bytes_length) {
      fail(`${path}: ${actual.length} bytes, expected ${expected.$bytes_length}`);
    }
    const crc = crc32(actual);
    if (crc !== expected.$bytes_crc32) fail(`${path}: CRC ${crc}, expected ${expected.$bytes_crc32}`);
    return;
  }
  if (expected === null) {
    if (!Number.isNaN(actual)) fail(`${path}: ${actual}, expected NaN`);
    return;
  }
  if (Array.isArray(expected)) {
    const list = Array.from(actual);
    if (list.length !== expected.length) fail(`${path}: ${list.length} elements, expected ${expected.length}`);
    expected.forEach((e, i) => compare(e, list[i], `${path}[${i}]`));
    return;
  }
  if (typeof expected === 'object') {
    const keys = Object.keys(actual).sort().join(',');
    const want = Object.keys(expected).sort().join(',');
    if (keys !== want) fail(`${path}: fields ${keys}, expected ${want}`);
    for (const k of Object.keys(expected)) compare(expected[k], actual[k], `${path}.${k}`);
    return;
  }
  if (expected !== actual) fail(`${path}: ${JSON.stringify(actual)}, expected ${JSON.stringify(expected)}`);
}

function streamRead(bytes, channels) {
  const reader = new McapStreamReader({ decompressHandlers, validateCrcs: true });
  reader.append(bytes);
  const schemas = new Map();
  const cache = new Map();
  const counts = {};
  let messages = 0;
  let footer = false;
  for (let record; (record = reader.nextRecord()) !== undefined;) {
    if (record.type === 'Schema') schemas.set(record.id, record);
    if (record.type === 'Channel') channels.set(record.id, record);
    if (record.type === 'Footer') footer = true;
    if (record.type !== 'Message') continue;
    const channel = channels.get(record.channelId);
    decode(decoderFor(schemas.get(channel.schemaId), cache), record.data, channel.topic);
    counts[channel.topic] = (counts[channel.topic] || 0) + 1;
    ++messages;
  }
  return { messages, counts, footer, done: reader.done() };
}

async function check(file, expectedFile) {
  const bytes = fs.readFileSync(file);
  const readable = {
    size: async () => BigInt(bytes.length),
    read: async (offset, size) => bytes.subarray(Number(offset), Number(offset + size)),
  };
  const reader = await McapIndexedReader.Initialize({ readable, decompressHandlers });
  if (reader.footer.summaryCrc === 0) fail('the footer has no summary CRC');
  const stats = reader.statistics ?? fail('no statistics record');
  if (reader.chunkIndexes.length === 0) fail('no chunk index');
  if (reader.chunkIndexes.length !== stats.chunkCount) fail('chunk indexes differ from the statistics');
  for (const index of reader.chunkIndexes) {
    if (index.messageIndexOffsets.size === 0 && index.messageEndTime > 0n) fail('a chunk without message indexes');
  }
  // The data section's CRC, from the first byte to the Data End record.
  const dataEnd = Number(reader.footer.summaryStart) - 13;
  if (bytes[dataEnd] !== 0x0f) fail('no Data End record before the summary');
  const dataCrc = bytes.readUInt32LE(dataEnd + 9);
  if (dataCrc === 0 || dataCrc !== crc32(bytes.subarray(0, dataEnd))) fail('data section CRC mismatch');

  const cache = new Map();
  const counts = new Map();
  const times = [];
  const { messages: expected = [], counts: expectedCounts = {} } =
    expectedFile ? JSON.parse(fs.readFileSync(expectedFile, 'utf8')) : {};
  const byTopic = new Map();
  let previous = -1n;
  for await (const message of reader.readMessages({ validateCrcs: true })) {
    const channel = reader.channelsById.get(message.channelId);
    if (channel.messageEncoding !== 'cdr') fail(`${channel.topic}: encoding ${channel.messageEncoding}`);
    if (!channel.metadata.has('offered_qos_profiles')) fail(`${channel.topic}: no offered_qos_profiles`);
    const schema = reader.schemasById.get(channel.schemaId);
    const value = decode(decoderFor(schema, cache), message.data, channel.topic);
    if (message.logTime < previous) fail('messages out of time order');
    previous = message.logTime;
    times.push(message.logTime);
    counts.set(message.channelId, (counts.get(message.channelId) || 0) + 1);
    const list = byTopic.get(channel.topic) || [];
    list.push(value);
    byTopic.set(channel.topic, list);
  }
  let total = 0;
  for (const [id, channel] of reader.channelsById) {
    const n = counts.get(id) || 0;
    const stated = Number(stats.channelMessageCounts.get(id) ?? -1);
    if (n !== stated) fail(`${channel.topic}: ${n} messages read, the statistics say ${stated}`);
    total += n;
  }
  if (BigInt(total) !== stats.messageCount) fail(`${total} messages read, the statistics say ${stats.messageCount}`);
  if (total > 0 && (times[0] !== stats.messageStartTime || times[times.length - 1] !== stats.messageEndTime)) {
    fail('message times differ from the statistics');
  }
  // A seek: from the middle of the time range, exactly the later messages.
  if (total > 0) {
    const middle = (stats.messageStartTime + stats.messageEndTime) / 2n;
    let later = 0;
    for await (const message of reader.readMessages({ startTime: middle, validateCrcs: true })) {
      if (message.logTime < middle) fail('a seek returned an earlier message');
      ++later;
    }
    const want = times.filter((t) => t >= middle).length;
    if (later !== want) fail(`a seek to the middle returned ${later} messages, expected ${want}`);
  }
  for (const e of expected) {
    const list = byTopic.get(e.topic) || fail(`${e.topic}: no messages`);
    if (e.index >= list.length) fail(`${e.topic}: no message ${e.index}`);
    compare(e.fields, list[e.index], `${e.topic}[${e.index}]`);
  }
  for (const [topic, n] of Object.entries(expectedCounts)) {
    const got = (byTopic.get(topic) || []).length;
    if (got !== n) fail(`${topic}: ${got} messages, expected ${n}`);
  }
  if (expectedFile && byTopic.size !== Object.keys(expectedCounts).length) {
    fail(`topics ${[...byTopic.keys()].join(', ')}; expected ${Object.keys(expectedCounts).join(', ')}`);
  }
  const streamed = streamRead(bytes, new Map());
  if (streamed.messages !== total || !streamed.footer) fail('the streaming reader disagrees');

  const topics = {};
  for (const [id, channel] of reader.channelsById) {
    topics[channel.topic] = {
      type: reader.schemasById.get(channel.schemaId).name,
      messages: counts.get(id) || 0,
    };
  }
  console.log(JSON.stringify({
    file, bytes: bytes.length, chunks: reader.chunkIndexes.length, messages: total,
    compared: expected.length, topics,
  }));
}

function partial(file) {
  const bytes = fs.readFileSync(file);
  const streamed = streamRead(bytes, new Map());
  if (streamed.footer) fail('the file is complete: not a partial file');
  console.log(JSON.stringify({
    file, bytes: bytes.length, messages: streamed.messages, topics: streamed.counts,
  }));
}

async function main() {
  await zstd.isLoaded;
  await lz4.isLoaded;
  const [mode, file, expected] = process.argv.slice(2);
  if (mode === 'check' && file) return check(file, expected);
  if (mode === 'partial' && file) return partial(file);
  fail('usage: check_mcap.js check FILE [EXPECTED] | partial FILE');
}

main().catch((e) => {
  console.error(`check_mcap: ${e.message}`);
  process.exit(1);
});
