// Connects to an arphys-view with the official Foxglove WebSocket client, subscribes to every
// advertised topic, decodes what arrives for DURATION_S seconds and writes it to OUT (JSON):
// the advertised channels, and per topic the message count and the decoded messages (images
// as their JPEG size and bytes, checked to be a JPEG).
//   node record_client.mjs ws://127.0.0.1:PORT DURATION_S OUT
import { writeFileSync } from "node:fs";
import protocol from "@foxglove/ws-protocol";
import WebSocket from "ws";

const { FoxgloveClient } = protocol;

const [url, durationS, out] = process.argv.slice(2);
if (!url || !durationS || !out) {
  console.error("usage: node record_client.mjs ws://HOST:PORT DURATION_S OUT.json");
  process.exit(2);
}

// Width and height from a JPEG's start-of-frame segment (baseline or progressive).
function jpegSize(bytes) {
  if (bytes[0] !== 0xff || bytes[1] !== 0xd8) return null;
  for (let i = 2; i + 9 < bytes.length; ) {
    if (bytes[i] !== 0xff) return null;
    const marker = bytes[i + 1];
    const length = (bytes[i + 2] << 8) | bytes[i + 3];
    if (marker === 0xc0 || marker === 0xc2) return { height: (bytes[i + 5] << 8) | bytes[i + 6], width: (bytes[i + 7] << 8) | bytes[i + 8] };
    i += 2 + length;
  }
  return null;
}

const client = new FoxgloveClient({ ws: new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]) });
const record = { serverInfo: null, channels: [], topics: {}, statuses: [] };
const topicOf = new Map();
const decoder = new TextDecoder();
client.on("serverInfo", (info) => (record.serverInfo = info));
client.on("status", (s) => record.statuses.push(s));
client.on("error", (e) => {
  console.error(`record_client: ${e.message ?? e}`);
  process.exit(1);
});
client.on("advertise", (channels) => {
  for (const channel of channels) {
    record.channels.push({ id: channel.id, topic: channel.topic, schemaName: channel.schemaName, encoding: channel.encoding });
    record.topics[channel.topic] = { count: 0, first_s: null, last_s: null, messages: [] };
    topicOf.set(client.subscribe(channel.id), channel.topic);
  }
});
client.on("message", ({ subscriptionId, data }) => {
  const topic = topicOf.get(subscriptionId);
  const entry = record.topics[topic];
  const t = performance.now() / 1000;
  entry.count += 1;
  entry.first_s ??= t;
  entry.last_s = t;
  const message = JSON.parse(decoder.decode(data));
  if (typeof message.data === "string") {  // a CompressedImage: keep its decoded size, not its bytes
    const bytes = Buffer.from(message.data, "base64");
    message.data = { bytes: bytes.length, jpeg: jpegSize(bytes) };
  }
  if (entry.messages.length < 400) entry.messages.push(message);
  if (topic === "/world") fetchModels(message);
});

// Each model a scene update references, fetched once over HTTP: its size in bytes (or the error).
record.models = {};
function fetchModels(update) {
  for (const entity of update.entities ?? [])
    for (const model of entity.models ?? []) {
      if (model.url in record.models) continue;
      record.models[model.url] = null;
      fetch(model.url)
        .then(async (r) => (record.models[model.url] = r.ok ? (await r.arrayBuffer()).byteLength : `HTTP ${r.status}`))
        .catch((e) => (record.models[model.url] = String(e)));
    }
}
setTimeout(() => {
  writeFileSync(out, JSON.stringify(record));
  client.close();
  process.exit(0);
}, Number(durationS) * 1000);
