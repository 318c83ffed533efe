// coug view: draws the scene the server sends over /ws on a canvas in local metres
// (x east, y north), with pan (drag) and zoom (wheel). Nothing is fetched but /ws.
"use strict";
const token = new URLSearchParams(location.search).get("token");
const scene = { vehicles: {}, shapes: {}, appcasts: {}, buttons: [], trailMax: 300, now: 0 };
const view = { cx: 0, cy: 0, scale: 2 }; // pixels per metre
const canvas = document.getElementById("map");
const ctx = canvas.getContext("2d");
let ws = null;

function connect() {
  const proto = location.protocol === "https:" ? "wss:" : "ws:";
  let url = proto + "//" + location.host + "/ws";
  if (token) url += "?token=" + encodeURIComponent(token);
  ws = new WebSocket(url);
  ws.onopen = () => status("connected");
  ws.onclose = () => { status("disconnected, retrying"); setTimeout(connect, 2000); };
  ws.onmessage = (ev) => handle(JSON.parse(ev.data));
}

function status(t) { document.getElementById("status").textContent = t; }

function shapeKey(s) { return s.kind + "/" + s.key; }

function handle(m) {
  if (m.type === "snapshot") {
    scene.vehicles = {}; scene.shapes = {}; scene.appcasts = {};
    scene.trailMax = m.trail_max; scene.buttons = m.buttons; drawButtons();
    for (const v of m.vehicles) scene.vehicles[v.name] = v;
  } else if (m.type === "delta") {
    for (const v of m.vehicles) {
      const old = scene.vehicles[v.name];
      const trail = (old ? old.trail : []).concat(v.trail_add);
      v.trail = trail.slice(Math.max(0, trail.length - scene.trailMax));
      scene.vehicles[v.name] = v;
    }
    for (const n of m.removed_vehicles) delete scene.vehicles[n];
    for (const [k, key] of m.removed_shapes) delete scene.shapes[k + "/" + key];
  } else if (m.type === "pressed" || m.type === "refused") {
    status(m.type + " " + (m.button || "") + (m.error ? ": " + m.error : ""));
    return;
  } else return;
  scene.now = m.now;
  for (const s of m.shapes) scene.shapes[shapeKey(s)] = s;
  for (const a of m.appcasts) scene.appcasts[a.node + "/" + a.app] = a;
  drawSide();
}

function drawButtons() {
  const div = document.getElementById("buttons");
  div.innerHTML = "";
  for (const b of scene.buttons) {
    const el = document.createElement("button");
    el.textContent = b.label;
    el.title = b.postings.map(p => p[0] + "=" + p[1]).join("\n");
    el.onclick = () => {
      if (confirm("Press " + b.label + "?\n" + el.title)) ws.send(JSON.stringify({ press: b.label }));
    };
    div.appendChild(el);
  }
}

function drawSide() {
  const vd = document.getElementById("vehicles");
  vd.innerHTML = "";
  for (const v of Object.values(scene.vehicles)) {
    const d = document.createElement("div");
    if (v.stale) d.className = "stale";
    const f = (x, n) => (x === null || x === undefined) ? "-" : x.toFixed(n);
    d.textContent = v.name + "  hdg " + f(v.heading, 0) + "  spd " + f(v.speed, 1) + "  dep " +
      f(v.depth, 1) + "  " + v.helm + " " + v.mode + (v.stale ? " (stale)" : "");
    vd.appendChild(d);
  }
  const sel = document.getElementById("cast");
  const keep = sel.value;
  const keys = Object.keys(scene.appcasts).sort();
  if (sel.options.length !== keys.length) {
    sel.innerHTML = "";
    for (const k of keys) { const o = document.createElement("option"); o.value = o.textContent = k; sel.appendChild(o); }
    if (keep) sel.value = keep;
  }
  const a = scene.appcasts[sel.value];
  document.getElementById("report").textContent = a ? a.report : "";
}
document.getElementById("cast").onchange = drawSide;

function toScreen(x, y) {
  return [canvas.width / 2 + (x - view.cx) * view.scale, canvas.height / 2 - (y - view.cy) * view.scale];
}

function grid() {
  const step = Math.pow(10, Math.ceil(Math.log10(50 / view.scale)));
  const [x0, y0] = [view.cx - canvas.width / 2 / view.scale, view.cy - canvas.height / 2 / view.scale];
  const [x1, y1] = [view.cx + canvas.width / 2 / view.scale, view.cy + canvas.height / 2 / view.scale];
  ctx.strokeStyle = "#1f3a4f"; ctx.lineWidth = 1; ctx.beginPath();
  for (let x = Math.floor(x0 / step) * step; x <= x1; x += step) { const [sx] = toScreen(x, 0); ctx.moveTo(sx, 0); ctx.lineTo(sx, canvas.height); }
  for (let y = Math.floor(y0 / step) * step; y <= y1; y += step) { const [, sy] = toScreen(0, y); ctx.moveTo(0, sy); ctx.lineTo(canvas.width, sy); }
  ctx.stroke();
  ctx.fillStyle = "#aaa"; ctx.fillText("grid " + step + " m", 8, canvas.height - 8);
}

function poly(pts, close) {
  ctx.beginPath();
  pts.forEach(([x, y], i) => { const [sx, sy] = toScreen(x, y); i ? ctx.lineTo(sx, sy) : ctx.moveTo(sx, sy); });
  if (close) ctx.closePath();
}

function label(s, x, y) {
  if (!s.label || s.label.startsWith("#")) return;
  const [sx, sy] = toScreen(x, y);
  ctx.fillStyle = s.label_color || "#ccc"; ctx.fillText(s.label, sx + 4, sy - 4);
}

function drawShape(s) {
  ctx.strokeStyle = s.edge_color || "#ccc";
  ctx.fillStyle = s.vertex_color || s.edge_color || "#ccc";
  ctx.lineWidth = s.edge_size || 1;
  switch (s.kind) {
    case "polygon": case "seglist":
      if (!s.pts.length) return;
      poly(s.pts, s.kind === "polygon"); ctx.stroke();
      if (s.fill_color && s.fill_transparency) { ctx.globalAlpha = s.fill_transparency; ctx.fillStyle = s.fill_color; ctx.fill(); ctx.globalAlpha = 1; }
      label(s, s.pts[0][0], s.pts[0][1]); break;
    case "point": {
      const [sx, sy] = toScreen(s.x, s.y); const r = s.vertex_size || 3;
      ctx.fillRect(sx - r / 2, sy - r / 2, r, r); label(s, s.x, s.y); break;
    }
    case "circle": case "range_pulse": {
      const r = s.radius || s.rad || 0; const [sx, sy] = toScreen(s.x, s.y);
      ctx.beginPath(); ctx.arc(sx, sy, r * view.scale, 0, 2 * Math.PI); ctx.stroke(); label(s, s.x, s.y); break;
    }
    case "marker": {
      const [sx, sy] = toScreen(s.x, s.y); const w = (s.width || 4) * view.scale;
      ctx.fillStyle = s.color || s.primary_color || "#ec0"; ctx.fillRect(sx - w / 2, sy - w / 2, w, w); label(s, s.x, s.y); break;
    }
    case "vector": case "arrow": {
      const x = s.x ?? s.cx, y = s.y ?? s.cy, ang = (s.ang ?? s.angle ?? 0) * Math.PI / 180, mag = s.mag ?? s.length ?? 10;
      poly([[x, y], [x + mag * Math.sin(ang), y + mag * Math.cos(ang)]], false); ctx.stroke(); label(s, x, y); break;
    }
    case "comms_pulse":
      poly([[s.sx, s.sy], [s.tx, s.ty]], false); ctx.stroke(); break;
  }
}

function drawVehicle(v) {
  if (v.x === null || v.y === null) return;
  ctx.strokeStyle = v.stale ? "#666" : "#6cf"; ctx.lineWidth = 1;
  if (v.trail.length > 1) { poly(v.trail, false); ctx.stroke(); }
  const [sx, sy] = toScreen(v.x, v.y);
  ctx.save(); ctx.translate(sx, sy); ctx.rotate((v.heading || 0) * Math.PI / 180);
  ctx.fillStyle = v.stale ? "#777" : (v.color || "yellow");
  ctx.beginPath(); ctx.moveTo(0, -10); ctx.lineTo(6, 8); ctx.lineTo(-6, 8); ctx.closePath(); ctx.fill();
  ctx.restore();
  ctx.fillStyle = v.stale ? "#888" : "#fff";
  ctx.fillText(v.name + (v.stale ? " (stale)" : ""), sx + 10, sy + 4);
}

function frame() {
  canvas.width = canvas.clientWidth; canvas.height = canvas.clientHeight;
  ctx.fillStyle = "#0b1d2a"; ctx.fillRect(0, 0, canvas.width, canvas.height);
  grid();
  for (const s of Object.values(scene.shapes)) drawShape(s);
  for (const v of Object.values(scene.vehicles)) drawVehicle(v);
  requestAnimationFrame(frame);
}

let drag = null;
canvas.onmousedown = (e) => { drag = [e.clientX, e.clientY]; };
window.onmouseup = () => { drag = null; };
window.onmousemove = (e) => {
  if (!drag) return;
  view.cx -= (e.clientX - drag[0]) / view.scale; view.cy += (e.clientY - drag[1]) / view.scale;
  drag = [e.clientX, e.clientY];
};
canvas.onwheel = (e) => { e.preventDefault(); view.scale *= e.deltaY < 0 ? 1.2 : 1 / 1.2; };

connect();
requestAnimationFrame(frame);
