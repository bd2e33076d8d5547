// The try-on viewer's client: one WebSocket to `lorgnette view` (protocol: viewer/protocol.h).
// Pointer and touch input become absolute orbit messages, at most one per animation frame; binary
// frames (24-byte LGNF header + JPEG/PNG) are drawn as they come, coarse ones scaled up. The page
// keeps no secrets and names no files: frames are picked by catalogue index.
"use strict";
(() => {
  const $ = (id) => document.getElementById(id);
  const canvas = $("view"), ctx = canvas.getContext("2d");
  const kinds = { 1: "coarse", 2: "full", 3: "snapshot" };
  // Exposed for the end-to-end test and for debugging from the console.
  const app = (window.lgnViewer = {
    ws: null, info: null, state: null, frames: 0, fullFrames: 0, lastFrame: null, errors: [], saved: [], fits: [],
    snapshots: 0, connected: false, lastSentSeq: 0, stateAt: 0, lastFullAt: 0,
    sendRaw: (text) => app.ws && app.ws.readyState === 1 && app.ws.send(text),
  });
  const orbit = { yaw: 0, pitch: 0, distance: 1, pan_x: 0, pan_y: 0 };
  app.orbit = orbit;  // read-only use, for the test and the console
  let limits = { yaw: [-60, 60], pitch: [-30, 30], distance: [0.55, 2], pan: 0.5 };
  let seq = 0, dirty = false, interacting = false, sentAt = new Map(), glassesOn = true;
  let fpsCount = 0, fpsStart = performance.now(), fps = 0;

  const clamp = (v, [lo, hi]) => Math.min(hi, Math.max(lo, v));
  const send = (obj) => app.sendRaw(JSON.stringify(obj));

  function queueCamera() {
    if (!dirty) requestAnimationFrame(flushCamera);
    dirty = true;
  }
  function flushCamera() {
    if (!dirty) return;
    dirty = false;
    seq = (seq + 1) >>> 0;
    sentAt.set(seq, performance.now());
    app.lastSentSeq = seq;
    if (sentAt.size > 256) sentAt.delete(sentAt.keys().next().value);
    send({ type: "camera", yaw: orbit.yaw, pitch: orbit.pitch, distance: orbit.distance,
           pan_x: orbit.pan_x, pan_y: orbit.pan_y, interacting, seq });
  }

  // --- input: drag to orbit, right/shift-drag or two fingers to pan, wheel or pinch to zoom ---
  const pointers = new Map();
  let pinch = null;
  canvas.addEventListener("contextmenu", (e) => e.preventDefault());
  canvas.addEventListener("pointerdown", (e) => {
    canvas.setPointerCapture(e.pointerId);
    pointers.set(e.pointerId, { x: e.clientX, y: e.clientY, pan: e.button === 2 || e.shiftKey });
    interacting = true;
    canvas.classList.add("dragging");
    if (pointers.size === 2) pinch = pinchState();
  });
  canvas.addEventListener("pointermove", (e) => {
    const p = pointers.get(e.pointerId);
    if (!p) return;
    const dx = e.clientX - p.x, dy = e.clientY - p.y, scale = 180 / canvas.clientWidth;
    p.x = e.clientX, p.y = e.clientY;
    if (pointers.size === 2 && pinch) {
      // Zoom from the pinch's start, not step by step: the two fingers' moves arrive one at a
      // time, and stepwise ratios would ratchet the distance against its limits while panning.
      const now = pinchState();
      orbit.distance = clamp(pinch.distance0 * pinch.d0 / Math.max(now.d, 1), limits.distance);
      pan(now.cx - pinch.cx, now.cy - pinch.cy);
      pinch.cx = now.cx, pinch.cy = now.cy;
    } else if (p.pan) {
      pan(dx, dy);
    } else {
      orbit.yaw = clamp(orbit.yaw - dx * scale, limits.yaw);
      orbit.pitch = clamp(orbit.pitch + dy * scale, limits.pitch);
    }
    queueCamera();
  });
  const release = (e) => {
    pointers.delete(e.pointerId);
    pinch = pointers.size === 2 ? pinchState() : null;
    if (pointers.size === 0) {
      interacting = false;
      canvas.classList.remove("dragging");
      queueCamera();
    }
  };
  canvas.addEventListener("pointerup", release);
  canvas.addEventListener("pointercancel", release);
  canvas.addEventListener("wheel", (e) => {
    e.preventDefault();
    orbit.distance = clamp(orbit.distance * Math.exp(e.deltaY * 0.001), limits.distance);
    queueCamera();
  }, { passive: false });
  function pan(dx, dy) {
    const k = (2 * limits.pan) / canvas.clientWidth;
    orbit.pan_x = clamp(orbit.pan_x - dx * k, [-limits.pan, limits.pan]);
    orbit.pan_y = clamp(orbit.pan_y + dy * k, [-limits.pan, limits.pan]);
  }
  function pinchState() {
    const [a, b] = [...pointers.values()];
    const d = Math.max(Math.hypot(a.x - b.x, a.y - b.y), 1);
    return { d, d0: d, distance0: orbit.distance, cx: (a.x + b.x) / 2, cy: (a.y + b.y) / 2 };
  }

  // --- buttons ---
  $("toggle").onclick = () => {
    glassesOn = !glassesOn;
    $("toggle").textContent = "Glasses: " + (glassesOn ? "on" : "off");
    send({ type: "glasses", on: glassesOn });
  };
  $("snapshot").onclick = () => send({ type: "snapshot" });
  $("reset-view").onclick = () => {
    Object.assign(orbit, { yaw: 0, pitch: 0, distance: 1, pan_x: 0, pan_y: 0 });
    queueCamera();
  };
  document.querySelectorAll("[data-nudge]").forEach((b) => {
    b.onclick = () => send({ type: "nudge", [b.dataset.nudge]: Number(b.dataset.amount) });
  });
  $("nudge-reset").onclick = () => send({ type: "nudge", reset: true });
  $("save").onclick = () => send({ type: "save" });

  // --- server messages ---
  function onText(msg) {
    if (msg.type === "info") {
      app.info = msg;
      limits = msg.limits;
      canvas.width = msg.viewport.width, canvas.height = msg.viewport.height;
      $("model").textContent = `${msg.model} · ${msg.device}`;
      buildCatalogue(msg.catalogue);
    } else if (msg.type === "state") {
      app.state = msg;
      app.stateAt = performance.now();
      showState(msg);
    } else if (msg.type === "fit") {
      app.fits.push(msg);
      showFit(msg);
    } else if (msg.type === "saved") {
      app.saved.push(msg);
      say(`saved ${msg.file}` + (msg.backup ? ` (previous kept as ${msg.backup})` : ""));
    } else if (msg.type === "error") {
      app.errors.push(msg);
      if (msg.code === "exists" && msg.request === "save") {
        if (confirm(msg.message + "\n\nReplace it?")) send({ type: "save", overwrite: true });
        else say("not saved");
      } else {
        say(`error (${msg.code}): ${msg.message}`);
      }
    }
  }

  // Where the scale came from and whether the frame is drawn at its real size.
  function scaleText(f) {
    if (!f.scale_source) return "–";
    const from = { card: "card", iris: "irises", "mean-face": "mean face (approximate)" }[f.scale_source] || f.scale_source;
    return f.scale_policy === "true-size" ? `${from}: real size` : `${from}: stretched, not the real size`;
  }
  const adviceLabel = { frame_width: "Fit: width", bridge: "Fit: bridge", temple_length: "Fit: temples", lens_height: "Fit: lens height" };
  function adviceText(r, approximate) {
    if (r.verdict === "not judged") return "not judged";
    const v = r.verdict === "good" ? "good" : `${r.verdict} by ${r.off_by_mm.toFixed(1)} mm`;
    return approximate ? v + " (approx.)" : v;
  }
  function showState(s) {
    const f = s.frame;
    document.querySelectorAll(".thumb").forEach((t) => t.setAttribute("aria-selected", String(Number(t.dataset.index) === f.index)));
    const mm = (v) => (v > 0 ? v.toFixed(1) + " mm" : "–");
    const facts = [
      ["Frame", f.name],
      ["PD (est.)", f.pd_mm ? f.pd_mm.toFixed(1) + (f.pd_uncertainty_mm ? " ± " + f.pd_uncertainty_mm.toFixed(1) : "") + " mm" : "–"],
      ["Scale", scaleText(f)],
      ["Size", `${mm(f.size_mm.lens_width)} □ ${mm(f.size_mm.bridge)} – ${mm(f.size_mm.temple)}`],
      ["Width", mm(f.size_mm.total_width)],
      ["Placement", f.status === "fitting" ? "fitting…" : f.source || "–"],
      ["Nudge", `${s.nudge.up_mm.toFixed(1)} mm up, ${s.nudge.forward_mm.toFixed(1)} mm fwd, ${s.nudge.tilt_deg.toFixed(0)}° tilt`],
      ...(f.advice || []).map((r) => [adviceLabel[r.name] || r.name, adviceText(r, f.advice_approximate)]),
    ];
    $("facts").replaceChildren(...facts.flatMap(([k, v]) => [el("dt", k), el("dd", v)]));
    $("fit-banner").hidden = f.status !== "fitting";
    if (f.status === "fitting") $("fit-banner").textContent = `fitting ${f.name}…`;
  }
  function showFit(m) {
    const banner = $("fit-banner");
    if (m.state === "started" || m.state === "progress") {
      banner.hidden = false;
      const stage = m.stage_label ? `: ${m.stage_label} (stage ${m.stage_index || 1})` : "";
      banner.textContent = `fitting frame ${m.frame}${stage}… ${m.elapsed_s ? m.elapsed_s + " s" : ""}`;
    } else {
      banner.hidden = true;
      say(m.state === "done" ? `fit done in ${m.seconds.toFixed(0)} s` + (m.message ? ` (${m.message})` : "")
                             : `fit failed: ${m.message}`);
    }
  }
  function buildCatalogue(items) {
    $("catalogue").replaceChildren(...items.map((it) => {
      const d = el("div", "");
      d.className = "thumb";
      d.dataset.index = it.index;
      d.setAttribute("role", "option");
      const img = document.createElement("img");
      img.src = it.thumbnail;
      img.alt = it.name;
      d.append(img, el("span", it.name));
      d.onclick = () => send({ type: "select", index: it.index });
      return d;
    }));
  }
  const el = (tag, text) => { const e = document.createElement(tag); e.textContent = text; return e; };
  const say = (text) => { $("message").textContent = text; };

  async function onBinary(buf) {
    const v = new DataView(buf);
    if (buf.byteLength < 24 || v.getUint32(0, false) !== 0x4c474e46) return;  // "LGNF"
    const kind = kinds[v.getUint8(5)], fseq = v.getUint32(8, true), w = v.getUint16(12, true), h = v.getUint16(14, true);
    const renderMs = v.getUint32(16, true) / 1000;
    const type = kind === "snapshot" ? "image/png" : "image/jpeg";
    const blob = new Blob([buf.slice(24)], { type });
    if (kind === "snapshot") {
      const link = $("snapshot-link");
      if (link.href) URL.revokeObjectURL(link.href);
      link.href = URL.createObjectURL(blob);
      link.hidden = false;
      app.snapshots++;
      say(`snapshot ${w}×${h} ready`);
      return;
    }
    const bmp = await createImageBitmap(blob);
    if (kind === "full" && (canvas.width !== w || canvas.height !== h)) canvas.width = w, canvas.height = h;
    ctx.imageSmoothingEnabled = true;
    ctx.drawImage(bmp, 0, 0, canvas.width, canvas.height);
    bmp.close();
    app.frames++;
    if (kind === "full") app.fullFrames++, (app.lastFullAt = performance.now());
    const t0 = sentAt.get(fseq), latency = t0 ? performance.now() - t0 : null;
    app.lastFrame = { kind, seq: fseq, width: w, height: h, renderMs, latencyMs: latency };
    fpsCount++;
    const now = performance.now();
    if (now - fpsStart > 1000) fps = (fpsCount * 1000) / (now - fpsStart), fpsCount = 0, fpsStart = now;
    $("hud").textContent = `${kind} ${w}×${h} · ${renderMs.toFixed(0)} ms` + (latency ? ` · ${latency.toFixed(0)} ms input→frame` : "") +
      ` · ${fps.toFixed(1)} fps`;
  }

  function connect() {
    const ws = new WebSocket(`ws://${location.host}/ws`);
    ws.binaryType = "arraybuffer";
    app.ws = ws;
    ws.onopen = () => { app.connected = true; $("status").textContent = "connected"; };
    ws.onclose = () => {
      app.connected = false;
      $("status").textContent = "disconnected: reconnecting…";
      setTimeout(connect, 1500);
    };
    ws.onmessage = (e) => {
      if (typeof e.data === "string") {
        try { onText(JSON.parse(e.data)); } catch (err) { console.warn("bad message", err); }
      } else {
        onBinary(e.data);
      }
    };
  }
  connect();
})();
