// coug view: draws the scene the server sends over /ws on a canvas in local metres
// (x east, y north). Nothing is fetched but /ws.
//
// The map fits the scene until the user pans or zooms: the box around every vehicle's
// position, every shape's points and the background image's corners (at least 20 m a
// side) is centred, scaled to leave
// 40 px on each side of the map canvas (window width minus the 320 px side panel, full
// height), so a given window size and scene give the same pixels (the browser tests compute
// positions with the same rule). window.cougView exposes the transform.
"use strict";
const token = new URLSearchParams(location.search).get("token");
const scene = { vehicles: {}, shapes: {}, appcasts: {}, buttons: [], contexts: [], trailMax: 300, now: 0, background: null };
// The background image (pMarineViewer's tiff_file, served as /background.png) once loaded.
let backImg = null;
function loadBackground(b) {
  scene.background = b || null;
  backImg = null;
  if (!b) return;
  const img = new Image();
  img.onload = () => { backImg = img; };
  img.src = b.url + (token ? "?token=" + encodeURIComponent(token) : "");
}
// `?follow=NAME` opens the page following that vehicle (as clicking it in the list does).
const view = { cx: 0, cy: 0, scale: 2, auto: true, follow: new URLSearchParams(location.search).get("follow") };
const history = {}; // vehicle name -> [[t, depth, speed]]
const PALETTE = ["#ffd700", "#ff4fa0", "#4fe34f", "#4fc3ff", "#ff8c1a", "#c77dff", "#ffffff", "#ff3030"];
const canvas = document.getElementById("map");
const ctx = canvas.getContext("2d");
let ws = null;
let replay = null;

function connect() {
  const proto = location.protocol === "https:" ? "wss:" : "ws:";
  let url = proto + "//" + location.host + "/ws";
  if (token) url += "?token=" + encodeURIComponent(token);
  ws = new WebSocket(url);
  ws.onopen = () => status("connected");
  ws.onclose = () => { status("disconnected, retrying"); setTimeout(connect, 2000); };
  ws.onmessage = (ev) => handle(JSON.parse(ev.data));
}

function send(obj) { if (ws && ws.readyState === 1) ws.send(JSON.stringify(obj)); }
function status(t) { document.getElementById("status").textContent = t; }
function shapeKey(s) { return s.kind + "/" + s.key; }

// A vehicle's colour: its report's COLOR, else the palette by its place in the sorted names.
function colorOf(v) {
  if (v.color) return v.color;
  const names = Object.keys(scene.vehicles).sort();
  return PALETTE[Math.max(0, names.indexOf(v.name)) % PALETTE.length];
}

function remember(v) {
  if (v.depth === null && v.speed === null) return;
  const h = history[v.name] || (history[v.name] = []);
  h.push([v.received, v.depth || 0, v.speed || 0]);
  while (h.length && h[0][0] < v.received - 300) h.shift();
}

function handle(m) {
  if (m.type === "snapshot") {
    scene.vehicles = {}; scene.shapes = {}; scene.appcasts = {};
    for (const k of Object.keys(history)) delete history[k];
    scene.trailMax = m.trail_max; scene.buttons = m.buttons; scene.contexts = m.contexts || [];
    if (JSON.stringify(m.background || null) !== JSON.stringify(scene.background)) loadBackground(m.background);
    drawButtons();
    // The server's history charts what came before the page opened.
    for (const v of m.vehicles) { scene.vehicles[v.name] = v; if (v.history) history[v.name] = v.history.slice(); else remember(v); }
  } else if (m.type === "delta") {
    for (const v of m.vehicles) {
      const old = scene.vehicles[v.name];
      const trail = (old ? old.trail : []).concat(v.trail_add);
      v.trail = trail.slice(Math.max(0, trail.length - scene.trailMax));
      scene.vehicles[v.name] = v;
      remember(v);
    }
    for (const n of m.removed_vehicles) delete scene.vehicles[n];
    for (const [k, key] of m.removed_shapes) delete scene.shapes[k + "/" + key];
  } else if (m.type === "status") {
    showReplay(m.replay); return;
  } else if (m.type === "pressed" || m.type === "refused") {
    status(m.type + " " + (m.button || m.context || "") + (m.error ? ": " + m.error : ""));
    return;
  } else return;
  scene.now = m.now;
  for (const s of m.shapes) scene.shapes[shapeKey(s)] = s;
  for (const a of m.appcasts) scene.appcasts[a.node + "/" + a.app] = a;
  if (m.replay) showReplay(m.replay);
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
      // Any posting can move a vehicle: every press is confirmed.
      if (confirm("Press " + b.label + "?\n" + el.title)) send({ press: b.label, vname: view.follow || undefined });
    };
    div.appendChild(el);
  }
}

function drawSide() {
  const vd = document.getElementById("vehicles");
  vd.innerHTML = "";
  for (const name of Object.keys(scene.vehicles).sort()) {
    const v = scene.vehicles[name];
    const d = document.createElement("div");
    d.className = (v.stale ? "stale" : "") + (view.follow === name ? " followed" : "");
    const sw = document.createElement("span");
    sw.className = "swatch"; sw.style.background = v.stale ? "#777" : colorOf(v);
    d.appendChild(sw);
    const f = (x, n) => (x === null || x === undefined) ? "-" : x.toFixed(n);
    d.appendChild(document.createTextNode(v.name + "  hdg " + f(v.heading, 0) + "  spd " + f(v.speed, 1) +
      "  dep " + f(v.depth, 1) + "  " + v.helm + " " + v.mode + (v.stale ? " (stale)" : "") +
      (view.follow === name ? "  [following]" : "")));
    d.title = "click: follow / stop following";
    d.onclick = () => { view.follow = view.follow === name ? null : name; drawSide(); };
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
  drawChart();
}
document.getElementById("cast").onchange = drawSide;

// Depth (blue, down) and speed (green) of the followed vehicle, else the first, over 300 s.
// What it charts is also written on the canvas (data-vehicle, data-points, data-left,
// data-top: its place on the page), for tests that read the page's DOM.
function drawChart() {
  const c = document.getElementById("chart"), g = c.getContext("2d");
  g.fillStyle = "#0b1d2a"; g.fillRect(0, 0, c.width, c.height);
  const name = view.follow || Object.keys(scene.vehicles).sort()[0];
  const h = name && history[name];
  const r = c.getBoundingClientRect();
  c.dataset.vehicle = name || ""; c.dataset.points = h ? h.length : 0;
  c.dataset.left = r.left; c.dataset.top = r.top;
  if (!h || !h.length) return;
  const t1 = h[h.length - 1][0], t0 = t1 - 300;
  const dmax = Math.max(1, ...h.map(p => p[1])), smax = Math.max(0.5, ...h.map(p => p[2]));
  const line = (idx, max, color, down) => {
    g.strokeStyle = color; g.beginPath();
    h.forEach((p, i) => {
      const x = (p[0] - t0) / 300 * c.width;
      const y = down ? 10 + p[idx] / max * (c.height - 20) : c.height - 10 - p[idx] / max * (c.height - 20);
      i ? g.lineTo(x, y) : g.moveTo(x, y);
    });
    g.stroke();
  };
  line(1, dmax, "#4fc3ff", true);
  line(2, smax, "#4fe34f", false);
  g.fillStyle = "#ccc";
  g.fillText(name + "  depth " + h[h.length - 1][1].toFixed(1) + " m (max " + dmax.toFixed(1) + ")", 4, 10);
  g.fillText("speed " + h[h.length - 1][2].toFixed(2) + " m/s (max " + smax.toFixed(2) + ")", 4, c.height - 2);
}

// The box every vehicle position and shape point lies in.
function sceneBox() {
  let b = null;
  const add = (x, y) => {
    if (typeof x !== "number" || typeof y !== "number") return;
    if (!b) b = [x, y, x, y];
    else { b[0] = Math.min(b[0], x); b[1] = Math.min(b[1], y); b[2] = Math.max(b[2], x); b[3] = Math.max(b[3], y); }
  };
  for (const v of Object.values(scene.vehicles)) add(v.x, v.y);
  const bg = scene.background;
  if (bg) { add(bg.left, bg.bottom); add(bg.right, bg.top); }
  for (const s of Object.values(scene.shapes)) {
    if (s.pts) for (const [x, y] of s.pts) add(x, y);
    else add(s.x, s.y);
  }
  return b;
}

function fit() {
  const b = sceneBox();
  if (!b) { view.cx = 0; view.cy = 0; view.scale = 2; return; }
  const dx = Math.max(b[2] - b[0], 20), dy = Math.max(b[3] - b[1], 20);
  view.scale = Math.min((canvas.width - 80) / dx, (canvas.height - 80) / dy);
  view.cx = (b[0] + b[2]) / 2; view.cy = (b[1] + b[3]) / 2;
}

function toScreen(x, y) {
  return [canvas.width / 2 + (x - view.cx) * view.scale, canvas.height / 2 - (y - view.cy) * view.scale];
}
function toWorld(px, py) {
  return [view.cx + (px - canvas.width / 2) / view.scale, view.cy - (py - canvas.height / 2) / view.scale];
}

function grid() {
  const step = Math.pow(10, Math.ceil(Math.log10(50 / view.scale)));
  const [x0, y0] = [view.cx - canvas.width / 2 / view.scale, view.cy - canvas.height / 2 / view.scale];
  const [x1, y1] = [view.cx + canvas.width / 2 / view.scale, view.cy + canvas.height / 2 / view.scale];
  ctx.strokeStyle = "#1f3a4f"; ctx.lineWidth = 1; ctx.beginPath();
  for (let x = Math.floor(x0 / step) * step; x <= x1; x += step) { const [sx] = toScreen(x, 0); ctx.moveTo(sx, 0); ctx.lineTo(sx, canvas.height); }
  for (let y = Math.floor(y0 / step) * step; y <= y1; y += step) { const [, sy] = toScreen(0, y); ctx.moveTo(0, sy); ctx.lineTo(canvas.width, sy); }
  ctx.stroke();
  // Scale bar: one grid step.
  ctx.strokeStyle = "#aaa"; ctx.beginPath();
  ctx.moveTo(8, canvas.height - 20); ctx.lineTo(8 + step * view.scale, canvas.height - 20); ctx.stroke();
  ctx.fillStyle = "#aaa"; ctx.fillText(step + " m", 8, canvas.height - 8);
}

function poly(pts, close) {
  ctx.beginPath();
  pts.forEach(([x, y], i) => { const [sx, sy] = toScreen(x, y); i ? ctx.lineTo(sx, sy) : ctx.moveTo(sx, sy); });
  if (close) ctx.closePath();
}

function label(s, x, y) {
  if (!s.label || s.label.startsWith("#")) return;
  const [sx, sy] = toScreen(x, y);
  ctx.fillStyle = s.label_color || "#ccc"; ctx.fillText(s.label, sx + 6, sy - 6);
}

function vertices(s) {
  const r = s.vertex_size || 5;
  ctx.fillStyle = s.vertex_color || s.edge_color || "#ccc";
  for (const [x, y] of s.pts) { const [sx, sy] = toScreen(x, y); ctx.fillRect(Math.round(sx - r / 2), Math.round(sy - r / 2), r, r); }
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
      vertices(s);
      label(s, s.pts[0][0], s.pts[0][1]); break;
    case "point": {
      const [sx, sy] = toScreen(s.x, s.y); const r = s.vertex_size || 3;
      ctx.fillRect(sx - r / 2, sy - r / 2, r, r); label(s, s.x, s.y); break;
    }
    case "circle": {
      const r = s.radius || s.rad || 0; const [sx, sy] = toScreen(s.x, s.y);
      ctx.beginPath(); ctx.arc(sx, sy, r * view.scale, 0, 2 * Math.PI); ctx.stroke(); label(s, s.x, s.y); break;
    }
    case "range_pulse": {
      // As pMarineViewer: the circle grows from nothing to `radius` over `duration` from t0
      // (then lingers), its fill fading from `fill` to nothing; green unless coloured.
      const dur = s.duration, el = scene.now - s.t0;
      if (!(dur > 0) || el < 0 || el > dur + (s.linger || 0)) break;
      const r = Math.min(1, el / dur) * (s.radius ?? 40), [sx, sy] = toScreen(s.x, s.y);
      const fill = s.fill ?? 0.25, degree = s.fill_invariant === "true" ? fill : Math.max(0, fill * (1 - el / dur));
      ctx.beginPath(); ctx.arc(sx, sy, r * view.scale, 0, 2 * Math.PI);
      if (degree > 0) { ctx.globalAlpha = degree; ctx.fillStyle = s.fill_color || "green"; ctx.fill(); ctx.globalAlpha = 1; }
      ctx.strokeStyle = s.edge_color || "green"; ctx.lineWidth = 1; ctx.stroke();
      label(s, s.x, s.y); break;
    }
    case "marker": {
      const [sx, sy] = toScreen(s.x, s.y); const w = (s.width || 4) * view.scale;
      ctx.fillStyle = s.color || s.primary_color || "#ec0"; ctx.fillRect(sx - w / 2, sy - w / 2, w, w); label(s, s.x, s.y); break;
    }
    case "vector": case "arrow": {
      const x = s.x ?? s.cx, y = s.y ?? s.cy, ang = (s.ang ?? s.angle ?? 0) * Math.PI / 180, mag = s.mag ?? s.length ?? 10;
      poly([[x, y], [x + mag * Math.sin(ang), y + mag * Math.cos(ang)]], false); ctx.stroke(); label(s, x, y); break;
    }
    case "comms_pulse": {
      // As pMarineViewer: a triangle from the source to a beam `beam_width` wide across the
      // target, filled (green unless coloured) and fading from `fill` over `duration`.
      const dur = s.duration, el = scene.now - s.t0;
      if (!(dur > 0) || el < 0 || el > dur) break;
      const ang = Math.atan2(s.tx - s.sx, s.ty - s.sy), hw = (s.beam_width ?? 10) / 2;
      const [px, py] = [hw * Math.cos(ang), -hw * Math.sin(ang)];
      poly([[s.sx, s.sy], [s.tx + px, s.ty + py], [s.tx - px, s.ty - py]], true);
      const degree = Math.max(0, (s.fill ?? 0.35) * (1 - el / dur));
      if (degree > 0) { ctx.globalAlpha = degree; ctx.fillStyle = s.fill_color || "green"; ctx.fill(); ctx.globalAlpha = 1; }
      label(s, s.sx, s.sy); break;
    }
  }
}

function drawVehicle(v) {
  if (v.x === null || v.y === null) return;
  const color = v.stale ? "#777" : colorOf(v);
  ctx.strokeStyle = color; ctx.globalAlpha = 0.6; ctx.lineWidth = 1;
  if (v.trail.length > 1) { poly(v.trail, false); ctx.stroke(); }
  ctx.globalAlpha = 1;
  const [sx, sy] = toScreen(v.x, v.y);
  ctx.save(); ctx.translate(sx, sy); ctx.rotate((v.heading || 0) * Math.PI / 180);
  ctx.fillStyle = color;
  ctx.beginPath(); ctx.moveTo(0, -12); ctx.lineTo(7, 9); ctx.lineTo(-7, 9); ctx.closePath(); ctx.fill();
  ctx.restore();
  ctx.fillStyle = v.stale ? "#888" : "#fff";
  ctx.fillText(v.name + (v.stale ? " (stale)" : ""), sx + 12, sy + 4);
}

function frame() {
  canvas.width = canvas.clientWidth; canvas.height = canvas.clientHeight;
  if (view.auto) fit();
  if (view.follow && scene.vehicles[view.follow]) { const v = scene.vehicles[view.follow]; view.cx = v.x; view.cy = v.y; }
  ctx.fillStyle = "#0b1d2a"; ctx.fillRect(0, 0, canvas.width, canvas.height);
  if (backImg && scene.background) {
    const b = scene.background;
    const [x0, y0] = toScreen(b.left, b.top), [x1, y1] = toScreen(b.right, b.bottom);
    ctx.drawImage(backImg, x0, y0, x1 - x0, y1 - y0);
  }
  grid();
  for (const s of Object.values(scene.shapes)) drawShape(s);
  for (const v of Object.values(scene.vehicles)) drawVehicle(v);
  requestAnimationFrame(frame);
}

function showReplay(r) {
  if (!r) return;
  replay = r;
  document.getElementById("replay").style.display = "block";
  const sl = document.getElementById("slider");
  sl.max = r.end;
  if (document.activeElement !== sl) sl.value = r.t;
  document.getElementById("clock").textContent = r.t.toFixed(1) + " / " + r.end.toFixed(1) + " s";
  document.getElementById("play").textContent = r.playing ? "pause" : "play";
}
document.getElementById("play").onclick = () => send({ replay: replay && replay.playing ? "pause" : "play" });
document.getElementById("slider").onchange = (e) => send({ replay: "seek", t: parseFloat(e.target.value) });
document.getElementById("speed").onchange = (e) => send({ replay: "speed", speed: parseFloat(e.target.value) });

// Right-click: the mission's context pokes at that spot, each confirmed before it is posted.
const menu = document.getElementById("menu");
canvas.oncontextmenu = (e) => {
  e.preventDefault();
  const keys = [];
  for (const c of scene.contexts) if (!c.key.startsWith("any_") && !keys.some(k => k[0] === c.side && k[1] === c.key)) keys.push([c.side, c.key]);
  if (!keys.length) return;
  const r = canvas.getBoundingClientRect();
  const [x, y] = toWorld(e.clientX - r.left, e.clientY - r.top);
  menu.innerHTML = "";
  for (const [side, key] of keys) {
    const d = document.createElement("div");
    d.textContent = key + " (" + side + ")";
    d.onclick = () => {
      menu.style.display = "none";
      const posts = scene.contexts.filter(c => c.side === side && (c.key === key || c.key === "any_" + side));
      const text = posts.map(c => c.var + " = " + c.value).join("\n");
      if (confirm("Post at x=" + x.toFixed(1) + ", y=" + y.toFixed(1) + "?\n" + text))
        send({ context: key, side: side, x: x, y: y, vname: view.follow || "" });
    };
    menu.appendChild(d);
  }
  menu.style.left = e.clientX + "px"; menu.style.top = e.clientY + "px"; menu.style.display = "block";
};
window.onclick = (e) => { if (!menu.contains(e.target)) menu.style.display = "none"; };

let drag = null;
canvas.onmousedown = (e) => { if (e.button === 0) drag = [e.clientX, e.clientY]; };
window.onmouseup = () => { drag = null; };
window.onmousemove = (e) => {
  if (!drag) return;
  view.auto = false; view.follow = null;
  view.cx -= (e.clientX - drag[0]) / view.scale; view.cy += (e.clientY - drag[1]) / view.scale;
  drag = [e.clientX, e.clientY];
};
canvas.onwheel = (e) => { e.preventDefault(); view.auto = false; view.scale *= e.deltaY < 0 ? 1.2 : 1 / 1.2; };
canvas.ondblclick = () => { view.auto = true; view.follow = null; };

window.cougView = { view, toScreen, toWorld, scene };
connect();
requestAnimationFrame(frame);
