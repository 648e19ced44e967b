// Watches a live view (urwire listen --foxglove) with Foxglove's own client of its WebSocket protocol
// (FoxgloveClient of @foxglove/ws-protocol, over the `ws` package: Node.js 20 has no WebSocket of its
// own), as a viewer does: it subscribes to each channel as it is advertised, and when the server closes
// the connection it prints as one JSON object the serverInfo, the channels as advertised, the statuses
// and every message (topic, log time, data as text), for tests/python/test_foxglove_listen.py.
// Usage: node watch_foxglove.mjs ws://HOST:PORT
import wsProtocol from "@foxglove/ws-protocol"; // CommonJS: its names come through the default export
import WebSocket from "ws";

const { FoxgloveClient } = wsProtocol;

const client = new FoxgloveClient({ ws: new WebSocket(process.argv[2], [FoxgloveClient.SUPPORTED_SUBPROTOCOL]) });
const text = new TextDecoder("utf-8", { fatal: true });
const out = { subprotocol: FoxgloveClient.SUPPORTED_SUBPROTOCOL, serverInfo: null, channels: [], statuses: [],
  messages: [] };
const topics = new Map(); // subscription id -> topic

client.on("serverInfo", (info) => { out.serverInfo = info; });
client.on("advertise", (channels) => {
  for (const channel of channels) {
    out.channels.push(channel);
    topics.set(client.subscribe(channel.id), channel.topic);
  }
});
client.on("message", ({ subscriptionId, timestamp, data }) => {
  out.messages.push({ topic: topics.get(subscriptionId), logTime: timestamp.toString(), data: text.decode(data) });
});
client.on("status", (status) => out.statuses.push(status));
client.on("error", (error) => { console.error(String(error)); process.exitCode = 1; });
client.on("close", () => process.stdout.write(JSON.stringify(out)));
