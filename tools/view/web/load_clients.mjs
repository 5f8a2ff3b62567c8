// Load on an arphys-view: COUNT clients that each connect, subscribe to every topic and leave
// after a random moment within SPREAD_S seconds, and STALLED clients that subscribe and then
// never read (their sockets paused, as a hung or half-open peer) until HOLD_S. Prints how many
// connected and how many were turned away.
//   node load_clients.mjs ws://HOST:PORT COUNT SPREAD_S STALLED HOLD_S
import WebSocket from "ws";

const [url, count, spreadS, stalled, holdS] = process.argv.slice(2);
if (!url || !holdS) {
  console.error("usage: node load_clients.mjs ws://HOST:PORT COUNT SPREAD_S STALLED HOLD_S");
  process.exit(2);
}
let opened = 0, failed = 0;
function client(stall) {
  const ws = new WebSocket(url, ["foxglove.websocket.v1"]);
  ws.on("error", () => failed++);
  ws.on("message", (data, isBinary) => {
    if (isBinary) return;
    const message = JSON.parse(data.toString());
    if (message.op !== "advertise") return;
    ws.send(JSON.stringify({ op: "subscribe", subscriptions: message.channels.map((c) => ({ id: c.id, channelId: c.id })) }));
    if (stall) ws._socket.pause();  // reads nothing more: the server's backlog for it grows
  });
  ws.on("open", () => {
    opened++;
    if (!stall) setTimeout(() => ws.terminate(), Math.random() * Number(spreadS) * 1000);
  });
}
for (let k = 0; k < Number(stalled); k++) client(true);
for (let k = 0; k < Number(count); k++) setTimeout(() => client(false), Math.random() * Number(spreadS) * 500);
setTimeout(() => {
  console.log(JSON.stringify({ opened, failed }));
  process.exit(0);
}, Number(holdS) * 1000);
