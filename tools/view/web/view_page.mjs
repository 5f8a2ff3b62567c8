// The page of arphys-view: a Foxglove WebSocket client (foxglove.websocket.v1, JSON messages)
// that shows the overlay stream, the world in 3D (three.js), the tracked objects, the
// processes and a latency strip chart. window.arphysView counts what was drawn (for tests).
import * as THREE from "three";
import { OBJLoader } from "three/addons/loaders/OBJLoader.js";

const state = { messages: {}, worldUpdates: 0, overlays: 0, bodies: 0, latencies: [] };
window.arphysView = state;

// --- 3D world -------------------------------------------------------------------------------
const container = document.getElementById("world");
const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setSize(container.clientWidth, container.clientHeight);
container.appendChild(renderer.domElement);
const scene = new THREE.Scene();
scene.background = new THREE.Color(0x2b2e33);
const camera = new THREE.PerspectiveCamera(45, container.clientWidth / container.clientHeight, 0.01, 50);
camera.up.set(0, 0, 1);
camera.position.set(0.9, -1.3, 1.0);
camera.lookAt(0, 0, 0.05);
scene.add(new THREE.HemisphereLight(0xffffff, 0x404040, 1.2));
const sun = new THREE.DirectionalLight(0xffffff, 1.5);
sun.position.set(1, -1, 2);
scene.add(sun);
const drawn = new THREE.Group();
scene.add(drawn);
const models = new Map();  // url -> loaded Object3D (null while loading)

// Each update redraws every body: geometries and materials are made once per size and colour
// and reused (made anew 50 times a second, they filled the GPU's memory: three.js frees them
// only on dispose()).
const made = new Map();
function once(key, make) {
  if (!made.has(key)) made.set(key, make());
  return made.get(key);
}
const material = (c) => once(`m ${c.r} ${c.g} ${c.b} ${c.a}`, () =>
  new THREE.MeshStandardMaterial({ color: new THREE.Color(c.r, c.g, c.b), transparent: c.a < 1, opacity: c.a }));
const box = (s) => once(`b ${s.x} ${s.y} ${s.z}`, () => new THREE.BoxGeometry(s.x, s.y, s.z));
const ball = (d) => once(`s ${d}`, () => new THREE.SphereGeometry(d / 2, 24, 16));
function place(object, pose) {
  object.position.set(pose.position.x, pose.position.y, pose.position.z);
  object.quaternion.set(pose.orientation.x, pose.orientation.y, pose.orientation.z, pose.orientation.w);
}
function model(url) {
  if (!models.has(url)) {
    models.set(url, null);
    new OBJLoader().load(url, (object) => models.set(url, object));
  }
  return models.get(url);
}

// A foxglove.SceneUpdate replaces what is drawn (arphys sends every body in each update).
function drawScene(update) {
  // The contact arrows' own materials (their geometries are three.js's, shared by all arrows).
  for (const arrow of drawn.children.filter((c) => c.type === "ArrowHelper")) {
    arrow.line.material.dispose();
    arrow.cone.material.dispose();
  }
  drawn.clear();
  let bodies = 0;
  for (const entity of update.entities) {
    for (const cube of entity.cubes ?? []) {
      const mesh = new THREE.Mesh(box(cube.size), material(cube.color));
      place(mesh, cube.pose);
      drawn.add(mesh);
      bodies++;
    }
    for (const sphere of entity.spheres ?? []) {
      const mesh = new THREE.Mesh(ball(sphere.size.x), material(sphere.color));
      place(mesh, sphere.pose);
      drawn.add(mesh);
      bodies++;
    }
    for (const m of entity.models ?? []) {
      const source = model(m.url);
      if (!source) continue;
      const copy = source.clone();
      const paint = material(m.color);
      copy.traverse((child) => { if (child.isMesh) child.material = paint; });
      copy.scale.set(m.scale.x, m.scale.y, m.scale.z);
      place(copy, m.pose);
      drawn.add(copy);
      bodies++;
    }
    for (const arrow of entity.arrows ?? []) {
      const q = new THREE.Quaternion(arrow.pose.orientation.x, arrow.pose.orientation.y, arrow.pose.orientation.z,
                                     arrow.pose.orientation.w);
      const p = arrow.pose.position;
      drawn.add(new THREE.ArrowHelper(new THREE.Vector3(1, 0, 0).applyQuaternion(q), new THREE.Vector3(p.x, p.y, p.z),
                                      arrow.shaft_length + arrow.head_length, 0xff3333));
    }
  }
  state.bodies = bodies;
  state.worldUpdates++;
}

// --- panels ---------------------------------------------------------------------------------
const overlay = document.getElementById("overlay");
function showImage(image) {
  overlay.src = `data:image/jpeg;base64,${image.data}`;
  state.overlays++;
}
function table(id, rows) {
  const t = document.getElementById(id);
  while (t.rows.length > 1) t.deleteRow(1);
  for (const { cells, cls } of rows) {
    const r = t.insertRow();
    if (cls) r.className = cls;
    for (const c of cells) r.insertCell().textContent = c;
  }
}
const processes = new Map();
function showStatus(s) {
  processes.set(s.name, s);
  table("processes", [...processes.values()].map((p) => ({
    cells: [p.name, p.state, p.rate_hz.toFixed(1), p.received, p.dropped] })));
  if (s.name === "replay")
    document.getElementById("position").textContent =
      `${s.figures.position_s.toFixed(1)} / ${s.figures.duration_s.toFixed(1)} s at ${s.figures.rate}x, ${s.state}`;
}
function showObjects(o) {
  table("objects", o.objects.map((x) => ({
    cls: x.status, cells: [x.id, x.status, x.reprojection_error_px.toFixed(2), x.markers_used, x.reason] })));
}
const chart = document.getElementById("latency");
function showLatency(l) {
  state.latencies.push(l.capture_to_publish_ms);
  if (state.latencies.length > 300) state.latencies.shift();
  const g = chart.getContext("2d");
  const top = Math.max(50, ...state.latencies);
  g.clearRect(0, 0, chart.width, chart.height);
  g.strokeStyle = "#4af";
  g.beginPath();
  state.latencies.forEach((v, i) => {
    const x = (i / 300) * chart.width, y = chart.height * (1 - v / top);
    i ? g.lineTo(x, y) : g.moveTo(x, y);
  });
  g.stroke();
  g.fillStyle = "#aaa";
  g.fillText(`${top.toFixed(0)} ms`, 4, 12);
  g.fillText(`last ${l.capture_to_publish_ms.toFixed(1)} ms`, 4, chart.height - 4);
}

// --- the protocol ---------------------------------------------------------------------------
const handlers = { "/world": drawScene, "/overlay": showImage, "/status": showStatus, "/latency": showLatency,
                   "/objects": showObjects };
const ws = new WebSocket(`ws://${location.host}/`, ["foxglove.websocket.v1"]);
ws.binaryType = "arraybuffer";
const topicOf = new Map();  // subscription id -> topic
const decoder = new TextDecoder();
ws.onopen = () => (document.getElementById("connection").textContent = "connected");
ws.onclose = () => (document.getElementById("connection").textContent = "disconnected");
// Client Message Data: opcode 1, the client's channel id (little-endian), the JSON payload.
const encoder = new TextEncoder();
function publish(channel, message) {
  const body = encoder.encode(JSON.stringify(message));
  const frame = new Uint8Array(5 + body.length);
  frame[0] = 1;
  new DataView(frame.buffer).setUint32(1, channel, true);
  frame.set(body, 5);
  ws.send(frame);
}

// What the server lets clients publish (clientPublish): with --allow-spawn a button drops the
// scene's first spawnable model above the table, a little off centre each time; with
// --allow-replay-control buttons pause, step, seek and change the rate of arphys-replay.
function offerControls(info) {
  if (!info.capabilities.includes("clientPublish")) return;
  const models = info.metadata?.spawn_models;
  const advertise = (id, topic) =>
    ws.send(JSON.stringify({ op: "advertise", channels: [{ id, topic, encoding: "json", schemaName: "arphys.Command" }] }));
  if (models) {
    advertise(1, "/spawn");
    const button = document.getElementById("spawn");
    button.hidden = false;
    button.onclick = () => publish(1, { model: models.split(",")[0],
      position: { x: (Math.random() - 0.5) * 0.3, y: (Math.random() - 0.5) * 0.2, z: 0.3 } });
  }
  if (info.metadata?.replay_control) {
    advertise(2, "/replay_control");
    document.getElementById("replay").hidden = false;
    for (const button of document.querySelectorAll("#replay button")) {
      button.onclick = () => {
        const replay = processes.get("replay")?.figures ?? {};
        const [command, change] = button.dataset.command.split(" ");
        const value = command === "seek" ? (replay.position_s ?? 0) + Number(change)
                    : command === "rate" ? (replay.rate ?? 1) * Number(change) : 0;
        publish(2, { command, value });
      };
    }
  }
}

ws.onmessage = (event) => {
  if (typeof event.data === "string") {
    const message = JSON.parse(event.data);
    if (message.op === "serverInfo") offerControls(message);
    if (message.op === "status") document.getElementById("connection").textContent = message.message;
    if (message.op !== "advertise") return;
    const subscriptions = message.channels
      .filter((c) => c.topic in handlers)
      .map((c) => ({ id: c.id, channelId: c.id }));
    for (const s of subscriptions) topicOf.set(s.id, message.channels.find((c) => c.id === s.channelId).topic);
    ws.send(JSON.stringify({ op: "subscribe", subscriptions }));
    return;
  }
  const view = new DataView(event.data);
  if (view.getUint8(0) !== 1) return;  // Message Data
  const topic = topicOf.get(view.getUint32(1, true));
  const message = JSON.parse(decoder.decode(new Uint8Array(event.data, 13)));
  state.messages[topic] = (state.messages[topic] ?? 0) + 1;
  handlers[topic]?.(message);
};

renderer.setAnimationLoop(() => renderer.render(scene, camera));
