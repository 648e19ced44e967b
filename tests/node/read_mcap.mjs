// Reads an MCAP file with Foxglove's own TypeScript reader (@mcap/core, as the Foxglove app does)
// and prints what it finds as one JSON object: the header, statistics, schemas, channels, chunk
// indexes, metadata and every message (its data as text), for tests/python/test_mcap_node.py.
// Usage: node read_mcap.mjs FILE.mcap
import { open } from "node:fs/promises";
import { McapIndexedReader } from "@mcap/core";
import { FileHandleReadable } from "@mcap/nodejs";
import zstd from "@foxglove/wasm-zstd";

await zstd.isLoaded;
const handle = await open(process.argv[2], "r");
const reader = await McapIndexedReader.Initialize({
  readable: new FileHandleReadable(handle),
  decompressHandlers: { zstd: (data, size) => zstd.decompress(data, Number(size)) },
});
const text = new TextDecoder("utf-8", { fatal: true });
const big = (_, value) => (typeof value === "bigint" ? value.toString() : value);
const out = {
  header: reader.header,
  statistics: reader.statistics && { ...reader.statistics,
    channelMessageCounts: Object.fromEntries(reader.statistics.channelMessageCounts) },
  schemas: [...reader.schemasById.values()].map((s) => ({ id: s.id, name: s.name, encoding: s.encoding,
    data: text.decode(s.data) })),
  channels: [...reader.channelsById.values()].map((c) => ({ id: c.id, topic: c.topic, schemaId: c.schemaId,
    messageEncoding: c.messageEncoding })),
  chunkIndexes: reader.chunkIndexes.map((c) => ({ messageStartTime: c.messageStartTime,
    messageEndTime: c.messageEndTime, compression: c.compression, channels: [...c.messageIndexOffsets.keys()] })),
  metadata: [],
  messages: [],
};
for await (const m of reader.readMetadata()) {
  out.metadata.push({ name: m.name, metadata: Object.fromEntries(m.metadata) });
}
for await (const m of reader.readMessages()) {
  const data = text.decode(m.data);
  JSON.parse(data); // strict JSON, as Foxglove parses a json message: throws on NaN
  out.messages.push({ channelId: m.channelId, sequence: m.sequence, logTime: m.logTime,
    publishTime: m.publishTime, data });
}
await handle.close();
process.stdout.write(JSON.stringify(out, big));
