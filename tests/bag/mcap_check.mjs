// Cairn's MCAP files as the reference implementation sees them (@mcap/core, Foxglove's own reader
// and writer; fzstd, an independent zstd decoder). Run by ctest (bag/app/CMakeLists.txt):
//   node mcap_check.mjs check FILE [--topic T]...   the indexed and the streaming reader both read
//       FILE: summary CRC, statistics, chunk and message indexes, every chunk CRC, the data-section
//       CRC, schemas and encodings, per-channel counts; each --topic must hold messages. Prints one
//       JSON line of what it found; exit 1 naming the first thing wrong.
//   node mcap_check.mjs decode-ros2 FILE   decodes every message on a ros2msg channel twice with
//       @foxglove/rosmsg2-serialization: with the standard definitions (@foxglove/rosmsg-msgs-common,
//       Jazzy) and with the file's own schema text; both must agree and make sense (a LaserScan's
//       ranges fit its angles, an Odometry's quaternion is a unit one). Prints counts per type.
//   node mcap_check.mjs write-reference FILE   writes a small file with the reference writer, for
//       Cairn's reader to read (bag tests).
import { readFile, writeFile } from "node:fs/promises";
import { McapIndexedReader, McapStreamReader, McapWriter, TempBuffer } from "@mcap/core";
import { crc32 } from "@foxglove/crc";
import { decompress } from "fzstd";
import { parse as parseMsg } from "@foxglove/rosmsg";
import { MessageReader } from "@foxglove/rosmsg2-serialization";
import { ros2jazzy } from "@foxglove/rosmsg-msgs-common";

const decompressHandlers = { zstd: (data, size) => decompress(data, new Uint8Array(Number(size))) };

function fail(what) {
  console.error(`mcap_check: ${what}`);
  process.exit(1);
}

async function check(path, topics) {
  const bytes = new Uint8Array(await readFile(path));
  const readable = {
    size: async () => BigInt(bytes.byteLength),
    read: async (offset, size) => bytes.subarray(Number(offset), Number(offset + size)),
  };
  const reader = await McapIndexedReader.Initialize({ readable, decompressHandlers });  // checks the summary CRC
  if (reader.header.profile !== "ros2") fail(`profile is "${reader.header.profile}", not ros2`);
  const stats = reader.statistics;
  if (!stats) fail("no Statistics record in the summary");
  if (reader.chunkIndexes.length !== stats.chunkCount) fail(`${reader.chunkIndexes.length} chunk indexes, statistics say ${stats.chunkCount}`);
  for (const op of [3, 4, 8, 11]) {
    if (!reader.summaryOffsetsByOpcode.has(op)) fail(`no SummaryOffset for opcode ${op}`);
  }
  for (const [id, channel] of reader.channelsById) {
    if (channel.messageEncoding !== "cdr") fail(`${channel.topic}: message encoding ${channel.messageEncoding}`);
    const schema = reader.schemasById.get(channel.schemaId);
    if (!schema || !["omgidl", "ros2msg"].includes(schema.encoding)) fail(`${channel.topic}: schema ${schema?.encoding}`);
  }
  // Every message through the indexes, with chunk CRCs checked, in log-time order.
  const counts = new Map();
  let previous = -1n, indexed = 0;
  for await (const m of reader.readMessages({ validateCrcs: true })) {
    if (m.logTime < previous) fail(`indexed messages out of time order at ${m.logTime}`);
    previous = m.logTime;
    counts.set(m.channelId, (counts.get(m.channelId) ?? 0) + 1);
    ++indexed;
  }
  if (BigInt(indexed) !== stats.messageCount) fail(`indexes reach ${indexed} messages, statistics say ${stats.messageCount}`);
  for (const [id, n] of stats.channelMessageCounts) {
    if (BigInt(counts.get(id) ?? 0) !== n) fail(`channel ${id}: ${counts.get(id) ?? 0} indexed, statistics say ${n}`);
  }
  // The whole file front to back, as a streaming consumer (a live viewer) reads it.
  const stream = new McapStreamReader({ decompressHandlers, validateCrcs: true });
  stream.append(bytes);
  let streamed = 0, dataEnd;
  for (let r; (r = stream.nextRecord()); ) {
    if (r.type === "Message") ++streamed;
    if (r.type === "DataEnd") dataEnd = r;
  }
  if (!stream.done()) fail("the stream reader did not reach the end of the file");
  if (streamed !== indexed) fail(`stream reader found ${streamed} messages, the indexes ${indexed}`);
  const dataCrc = crc32(bytes.subarray(0, Number(reader.dataEndOffset)));
  if (!dataEnd || dataEnd.dataSectionCrc !== dataCrc) fail(`data section CRC ${dataEnd?.dataSectionCrc}, computed ${dataCrc}`);
  const byTopic = {};
  for (const [id, channel] of reader.channelsById) byTopic[channel.topic] = counts.get(id) ?? 0;
  for (const t of topics) {
    if (!byTopic[t]) fail(`no messages on ${t}`);
  }
  console.log(JSON.stringify({ messages: indexed, chunks: stats.chunkCount, channels: reader.channelsById.size,
                               schemas: reader.schemasById.size, topics: byTopic }));
}

// "sensor_msgs/msg/LaserScan" -> reader built from the standard definitions.
function standardReader(type) {
  const name = type.replace("/msg/", "/");
  const root = ros2jazzy[name];
  if (!root) fail(`no standard definition for ${type}`);
  return new MessageReader([root, ...Object.values(ros2jazzy).filter((d) => d !== root)]);
}

const seen = { map: undefined, markers: undefined, tf: new Set(), paths: {} };

function sane(type, m, where) {
  if (type === "nav_msgs/msg/OccupancyGrid") {
    if (m.data.length !== m.info.width * m.info.height) fail(`${where}: ${m.data.length} cells for ${m.info.width}x${m.info.height}`);
    if (!(m.info.resolution > 0)) fail(`${where}: resolution ${m.info.resolution}`);
    seen.map = { width: m.info.width, height: m.info.height, resolution: Math.round(m.info.resolution * 1e6) / 1e6,
                 known: m.data.filter((v) => v !== -1).length };
  } else if (type === "visualization_msgs/msg/MarkerArray") {
    if (m.markers[0]?.action !== 3) fail(`${where}: does not start with DELETEALL`);
    seen.markers = m.markers.length;
  } else if (type === "tf2_msgs/msg/TFMessage") {
    for (const t of m.transforms) seen.tf.add(`${t.header.frame_id}->${t.child_frame_id}`);
  } else if (type === "nav_msgs/msg/Path") {
    seen.paths[where.split(" ")[0]] = m.poses.length;
  }
  if (type === "sensor_msgs/msg/LaserScan") {
    const beams = Math.round((m.angle_max - m.angle_min) / m.angle_increment) + 1;
    if (beams !== m.ranges.length) fail(`${where}: ${m.ranges.length} ranges for ${beams} beams`);
  } else if (type === "nav_msgs/msg/Odometry") {
    const q = m.pose.pose.orientation;
    if (Math.abs(Math.hypot(q.x, q.y, q.z, q.w) - 1) > 1e-6) fail(`${where}: orientation is not a unit quaternion`);
  }
  if (m.header && !(m.header.stamp.sec > 0)) fail(`${where}: no stamp`);
}

async function decodeRos2(path) {
  const bytes = new Uint8Array(await readFile(path));
  const stream = new McapStreamReader({ decompressHandlers, validateCrcs: true });
  stream.append(bytes);
  const schemas = new Map(), channels = new Map(), counts = {};
  for (let r; (r = stream.nextRecord()); ) {
    if (r.type === "Schema") schemas.set(r.id, r);
    else if (r.type === "Channel") {
      const schema = schemas.get(r.schemaId);
      if (schema?.encoding !== "ros2msg") continue;
      const ownText = new TextDecoder().decode(schema.data);
      channels.set(r.id, { topic: r.topic, type: schema.name, standard: standardReader(schema.name),
                           own: new MessageReader(parseMsg(ownText, { ros2: true })) });
    } else if (r.type === "Message" && channels.has(r.channelId)) {
      const c = channels.get(r.channelId);
      const where = `${c.topic} message ${r.sequence}`;
      const m = c.standard.readMessage(r.data);
      const own = c.own.readMessage(r.data);
      if (JSON.stringify(m) !== JSON.stringify(own)) fail(`${where}: the file's schema decodes it differently`);
      sane(c.type, m, where);
      counts[c.type] = (counts[c.type] ?? 0) + 1;
    }
  }
  if (channels.size === 0) fail("no ros2msg channel");
  console.log(JSON.stringify({ counts, map: seen.map, markers: seen.markers, tf: [...seen.tf].sort(), paths: seen.paths }));
}

async function writeReference(path) {
  const buffer = new TempBuffer();
  const writer = new McapWriter({ writable: buffer, chunkSize: 1024 });
  await writer.start({ profile: "ros2", library: "@mcap/core reference" });
  const schemaId = await writer.registerSchema({ name: "cairn_msgs::Odometry", encoding: "omgidl", data: new TextEncoder().encode("struct Odometry { double x; };") });
  const a = await writer.registerChannel({ topic: "reference/a", messageEncoding: "cdr", schemaId, metadata: new Map([["k", "v"]]) });
  const b = await writer.registerChannel({ topic: "reference/b", messageEncoding: "cdr", schemaId, metadata: new Map() });
  for (let i = 0; i < 100; ++i) {
    const data = new Uint8Array(20 + (i % 5)).fill(i);
    await writer.addMessage({ channelId: i % 3 ? a : b, sequence: i, logTime: BigInt(1000 + i), publishTime: BigInt(1000 + i), data });
  }
  await writer.end();
  await writeFile(path, buffer.get());
}

const [mode, path, ...rest] = process.argv.slice(2);
const topics = rest.flatMap((arg, i) => (rest[i - 1] === "--topic" ? [arg] : []));
try {
  if (mode === "check") await check(path, topics);
  else if (mode === "decode-ros2") await decodeRos2(path);
  else if (mode === "write-reference") await writeReference(path);
  else fail("usage: mcap_check.mjs check FILE [--topic T]... | decode-ros2 FILE | write-reference FILE");
} catch (e) {
  fail(`${path}: ${e.message}`);
}
