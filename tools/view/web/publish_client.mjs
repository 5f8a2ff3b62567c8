// Publishes through an arphys-view with the official Foxglove client (clientPublish): each
// argument after the URL is TOPIC=JSON (advertised on first use, then sent) or wait=MS; prints
// the server's capabilities, metadata and the status messages it sent back, as JSON.
//   node publish_client.mjs ws://HOST:PORT '/spawn={"model":"bunny",...}' wait=150 ...
import protocol from "@foxglove/ws-protocol";
import WebSocket from "ws";

const { FoxgloveClient } = protocol;
const [url, ...steps] = process.argv.slice(2);
const client = new FoxgloveClient({ ws: new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]) });
const statuses = [];
const channels = new Map();
const encoder = new TextEncoder();
const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));
client.on("status", (s) => statuses.push(s.message));
client.on("serverInfo", async (info) => {
  await sleep(100);
  for (const step of steps) {
    const at = step.indexOf("=");
    const [key, value] = [step.slice(0, at), step.slice(at + 1)];
    if (key === "wait") {
      await sleep(Number(value));
      continue;
    }
    if (!channels.has(key)) channels.set(key, client.advertise({ topic: key, encoding: "json", schemaName: "arphys.Command" }));
    client.sendMessage(channels.get(key), encoder.encode(value));
  }
  await sleep(500);
  console.log(JSON.stringify({ capabilities: info.capabilities, metadata: info.metadata, statuses }));
  client.close();
  process.exit(0);
});
