#!/usr/bin/env node
// Reads an MCAP file with Foxglove's own @mcap/core, an implementation independent of vifusion's, and
// prints what it finds as JSON lines: one per message (topic, schema, encodings, ids, times, size, first
// bytes, CRC-32 of the data), then one summary line.
//
//   node read_mcap.mjs --indexed FILE [--expect EXPECTED.jsonl]   McapIndexedReader: a complete file,
//                                                                 through its footer and summary
//   node read_mcap.mjs --stream FILE [--expect EXPECTED.jsonl]    McapStreamReader: any file front to
//                                                                 back, a cut one included
//
// With --expect, the lines must equal those of EXPECTED.jsonl (compared as JSON values, key order aside);
// the first difference is printed and the exit code is 1. u64 values (times, counts) are decimal strings.
//
// What McapStreamReader does with a file cut inside a record: nextRecord() returns undefined as if more
// bytes were still to come (no error), done() stays false, and bytesRemaining() is the number of bytes of
// the partial record; the summary reports both as "done" and "trailing_bytes".

import { open, readFile } from "node:fs/promises";

const usage = "usage: node read_mcap.mjs (--indexed | --stream) FILE [--expect EXPECTED.jsonl]";
const installHint = "run .ci/install-deps (it runs npm ci in tests/node)";

let mcap;
let crc32;
try {
  mcap = await import("@mcap/core");
  // @mcap/core's own CRC-32 (a dependency pinned by package-lock.json): Node 18, Debian 12's, has no zlib.crc32.
  ({ crc32 } = await import("@foxglove/crc"));
} catch (error) {
  console.error(`read_mcap.mjs: cannot load @mcap/core from tests/node/node_modules (${error.message}): ${installHint}`);
  process.exit(2);
}

function parseArguments(argv) {
  const args = { mode: undefined, file: undefined, expect: undefined };
  for (let i = 0; i < argv.length; ++i) {
    if (argv[i] === "--indexed" || argv[i] === "--stream") {
      args.mode = argv[i].slice(2);
      args.file = argv[++i];
    } else if (argv[i] === "--expect") {
      args.expect = argv[++i];
    } else {
      throw new Error(`unknown argument ${argv[i]}; ${usage}`);
    }
  }
  if (!args.mode || !args.file) throw new Error(usage);
  return args;
}

const hex = (bytes) => Array.from(bytes, (b) => b.toString(16).padStart(2, "0")).join("");
const kHeadBytes = 8;

/** One JSON object per message; `schemas` and `channels` are Maps by id. */
function describeMessage(message, channels, schemas) {
  const channel = channels.get(message.channelId);
  const schema = schemas.get(channel.schemaId);
  return {
    topic: channel.topic,
    schema: schema ? schema.name : "",
    schema_encoding: schema ? schema.encoding : "",
    message_encoding: channel.messageEncoding,
    channel_id: message.channelId,
    sequence: message.sequence,
    log_time: message.logTime.toString(),
    publish_time: message.publishTime.toString(),
    size: message.data.byteLength,
    head: hex(message.data.subarray(0, kHeadBytes)),
    crc32: crc32(message.data),
  };
}

function describeAttachment(attachment) {
  return {
    name: attachment.name,
    media_type: attachment.mediaType,
    log_time: attachment.logTime.toString(),
    size: attachment.data.byteLength,
    crc32: crc32(attachment.data),
  };
}

async function readIndexed(path) {
  const handle = await open(path, "r");
  try {
    const size = BigInt((await handle.stat()).size);
    const readable = {
      size: async () => size,
      read: async (offset, length) => {
        const buffer = new Uint8Array(Number(length));
        const { bytesRead } = await handle.read(buffer, 0, buffer.byteLength, Number(offset));
        if (bytesRead !== buffer.byteLength) throw new Error(`${path}: short read at ${offset}`);
        return buffer;
      },
    };
    const reader = await mcap.McapIndexedReader.Initialize({ readable });
    const lines = [];
    for await (const message of reader.readMessages({ validateCrcs: true })) {
      lines.push(describeMessage(message, reader.channelsById, reader.schemasById));
    }
    const attachments = [];
    for await (const attachment of reader.readAttachments({ validateCrcs: true })) {
      attachments.push(describeAttachment(attachment));
    }
    const statistics = reader.statistics;
    const channelCounts = {};
    for (const [id, count] of statistics?.channelMessageCounts ?? []) channelCounts[id] = count.toString();
    lines.push({
      summary: {
        reader: "indexed",
        profile: reader.header.profile,
        library: reader.header.library,
        messages: lines.length,
        schemas: reader.schemasById.size,
        channels: reader.channelsById.size,
        chunks: reader.chunkIndexes.length,
        attachments,
        statistics: statistics && {
          message_count: statistics.messageCount.toString(),
          chunk_count: statistics.chunkCount,
          attachment_count: statistics.attachmentCount,
          message_start_time: statistics.messageStartTime.toString(),
          message_end_time: statistics.messageEndTime.toString(),
          channel_message_counts: channelCounts,
        },
      },
    });
    return lines;
  } finally {
    await handle.close();
  }
}

async function readStream(path) {
  const reader = new mcap.McapStreamReader({ includeChunks: true, validateCrcs: true });
  reader.append(await readFile(path));
  const schemas = new Map();
  const channels = new Map();
  const lines = [];
  const attachments = [];
  let header;
  let chunks = 0;
  for (let record; (record = reader.nextRecord()); ) {
    switch (record.type) {
      case "Header":
        header = record;
        break;
      case "Schema":
        schemas.set(record.id, record);
        break;
      case "Channel":
        channels.set(record.id, record);
        break;
      case "Chunk":
        ++chunks;
        break;
      case "Attachment":
        attachments.push(describeAttachment(record));
        break;
      case "Message":
        lines.push(describeMessage(record, channels, schemas));
        break;
      default:
        break;
    }
  }
  lines.push({
    summary: {
      reader: "stream",
      profile: header?.profile,
      library: header?.library,
      messages: lines.length,
      schemas: schemas.size,
      channels: channels.size,
      chunks,
      attachments,
      done: reader.done(),
      trailing_bytes: reader.bytesRemaining(),
    },
  });
  return lines;
}

/** JSON with object keys sorted, so that key order does not matter in the comparison. */
function canonical(value) {
  if (Array.isArray(value)) return `[${value.map(canonical).join(",")}]`;
  if (value && typeof value === "object") {
    return `{${Object.keys(value)
      .sort()
      .map((key) => `${JSON.stringify(key)}:${canonical(value[key])}`)
      .join(",")}}`;
  }
  return JSON.stringify(value);
}

async function compare(lines, expectedPath) {
  const expected = (await readFile(expectedPath, "utf8"))
    .split("\n")
    .filter((line) => line.length > 0)
    .map((line) => JSON.parse(line));
  const count = Math.max(lines.length, expected.length);
  for (let i = 0; i < count; ++i) {
    const got = i < lines.length ? canonical(lines[i]) : "(nothing)";
    const want = i < expected.length ? canonical(expected[i]) : "(nothing)";
    if (got !== want) {
      console.error(`line ${i + 1} of ${count} differs:\n  @mcap/core: ${got}\n  expected:   ${want}`);
      return false;
    }
  }
  console.error(`read_mcap.mjs: all ${count} lines agree with ${expectedPath}`);
  return true;
}

try {
  const args = parseArguments(process.argv.slice(2));
  const lines = args.mode === "indexed" ? await readIndexed(args.file) : await readStream(args.file);
  if (args.expect) {
    process.exit((await compare(lines, args.expect)) ? 0 : 1);
  }
  for (const line of lines) console.log(JSON.stringify(line));
} catch (error) {
  console.error(`read_mcap.mjs: ${error.message}`);
  process.exit(1);
}
