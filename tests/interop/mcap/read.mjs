// SPDX-License-Identifier: Apache-2.0
// An independent MCAP reader for the McapInterop.* tests of ncqual_mcap: Foxglove's @mcap/core
// (the reference TypeScript implementation) with its wasm zstd and lz4 decompressors, versions
// pinned in package.json/package-lock.json (install: npm ci --prefix tests/interop/mcap).
//
// Usage: node read.mjs [--stream] FILE
//   default:  McapIndexedReader (footer, summary, chunk and message indexes; CRCs validated)
//   --stream: McapStreamReader, every record from the start (an unindexed or truncated file)
// Prints one JSON object on stdout: {"reader","profile","library","channels":[{"id","topic",
// "messageEncoding","schemaId","schemaName","metadata"}],"schemas":[{"id","name","encoding",
// "dataHex"}],"messageCount","messages":[{"channel","sequence","logTime","publishTime",
// "dataHex"}]} with times as decimal strings (they are 64-bit); --stream adds "complete" (the
// reader reached the closing magic). Errors go to stderr with exit code 1.
import { open } from "node:fs/promises";
import { McapIndexedReader, McapStreamReader } from "@mcap/core";
import * as zstd from "@foxglove/wasm-zstd";
import lz4 from "@foxglove/wasm-lz4";

const hex = (bytes) => Buffer.from(bytes.buffer, bytes.byteOffset, bytes.byteLength).toString("hex");

const decompressHandlers = {
  zstd: (buffer, size) => zstd.decompress(buffer, Number(size)),
  lz4: (buffer, size) => lz4(buffer, Number(size)),
};

function describe(reader, header, schemas, channels, messages) {
  return {
    reader,
    profile: header.profile,
    library: header.library,
    channels: [...channels.values()].map((c) => ({
      id: c.id,
      topic: c.topic,
      messageEncoding: c.messageEncoding,
      schemaId: c.schemaId,
      schemaName: schemas.get(c.schemaId)?.name ?? "",
      metadata: Object.fromEntries(c.metadata),
    })),
    schemas: [...schemas.values()].map((s) => ({
      id: s.id,
      name: s.name,
      encoding: s.encoding,
      dataHex: hex(s.data),
    })),
    messageCount: messages.length,
    messages: messages.map((m) => ({
      channel: m.channelId,
      sequence: m.sequence,
      logTime: m.logTime.toString(),
      publishTime: m.publishTime.toString(),
      dataHex: hex(m.data),
    })),
  };
}

async function readIndexed(path) {
  const handle = await open(path, "r");
  try {
    const readable = {
      size: async () => BigInt((await handle.stat()).size),
      read: async (offset, size) => {
        const buffer = new Uint8Array(Number(size));
        const { bytesRead } = await handle.read(buffer, 0, buffer.length, Number(offset));
        if (bytesRead !== buffer.length) throw new Error(`short read at ${offset}`);
        return buffer;
      },
    };
    const reader = await McapIndexedReader.Initialize({ readable, decompressHandlers });
    const messages = [];
    for await (const m of reader.readMessages({ validateCrcs: true })) messages.push(m);
    return describe("indexed", reader.header, reader.schemasById, reader.channelsById, messages);
  } finally {
    await handle.close();
  }
}

async function readStream(path) {
  const handle = await open(path, "r");
  const bytes = await handle.readFile();
  await handle.close();
  const reader = new McapStreamReader({ decompressHandlers, validateCrcs: true });
  reader.append(bytes);
  let header = { profile: "", library: "" };
  const schemas = new Map();
  const channels = new Map();
  const messages = [];
  let dataEnded = false;
  for (let record; (record = reader.nextRecord()); ) {
    if (record.type === "DataEnd") dataEnded = true;
    if (dataEnded) continue; // the summary repeats schemas and channels
    if (record.type === "Header") header = record;
    else if (record.type === "Schema" && !schemas.has(record.id)) schemas.set(record.id, record);
    else if (record.type === "Channel" && !channels.has(record.id)) channels.set(record.id, record);
    else if (record.type === "Message") messages.push(record);
  }
  return { ...describe("stream", header, schemas, channels, messages), complete: reader.done() };
}

const args = process.argv.slice(2);
const stream = args[0] === "--stream";
const path = stream ? args[1] : args[0];
if (!path) {
  process.stderr.write("usage: node read.mjs [--stream] FILE\n");
  process.exit(2);
}
try {
  await zstd.isLoaded;
  await lz4.isLoaded;
  const result = stream ? await readStream(path) : await readIndexed(path);
  process.stdout.write(JSON.stringify(result) + "\n");
} catch (error) {
  process.stderr.write(`read.mjs: ${path}: ${error.stack ?? error}\n`);
  process.exit(1);
}
