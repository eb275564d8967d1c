// Throng view: draws the gateway's stream top-down and sends the keyboard/mouse as input.
// Messages from the gateway (WebSocket /ws, JSON text): "match" (scenery, roster, bounds), "frame"
// (poses at the snapshot rate, measured latency/bandwidth), "error" (our input was rejected).
// Replay mode (match.mode === "replay", throng-view --log): frames carry every body and a
// "replay" timeline; "timeline" messages update it alone (e.g. a seek starting). The page sends
// play/pause/toggle/speed/seek/focus instead of input, and no keyboard ever moves anything.
// Collision overlay (C): collision shapes, and for each contact pair the server (live) or the
// re-simulation (replay) reports near the camera, the contact plane at the push-ratio point (the
// patent's virtual plane VP1) with the ratio as text. Live, the request rides on every input as
// the contacts action bit; in a replay the page sends {"type":"contacts", on, camera_x/y}.
// World coordinates: metres, x right, y up; the canvas flips y.
'use strict';
(() => {
  const FACTION_COLORS = ['#9aa0a6', '#e4572e', '#2e86de', '#f2c14e', '#4caf50', '#a05195', '#17becf', '#c49c94'];
  const BACKGROUND = '#1b1f24';
  const ACTION_SPRINT = 1, ACTION_BRACE = 2, ACTION_CONTACTS = 4;  // protocol kAction* bits
  const PLANE_COLOR = '#ff4081';
  const MOVE_KEYS = {
    KeyW: [0, 1], ArrowUp: [0, 1], KeyS: [0, -1], ArrowDown: [0, -1],
    KeyA: [-1, 0], ArrowLeft: [-1, 0], KeyD: [1, 0], ArrowRight: [1, 0],
  };

  const canvas = document.getElementById('view');
  const ctx = canvas.getContext('2d');
  const $ = (id) => document.getElementById(id);

  const view = {
    ws: null, connected: false, match: null, roster: new Map(), frame: null, frames: 0,
    zoom: 16, center: { x: 0, y: 0 }, panned: false, showShapes: false,
    keys: new Set(), facing: 0, mouse: null, aimWithMouse: false, drag: null,
    drawn: 0, drawnObjects: 0, frameAt: 0, sent: 0, errors: 0, lastError: null,
    replay: null, followId: 0, scrubbing: false, lastSeekSent: 0, fitted: false,
    contactsDrawn: [], contactsSent: null,
  };
  const isReplay = () => !!(view.match && view.match.mode === 'replay');

  // --- connection ---------------------------------------------------------------------------
  function connect() {
    const ws = new WebSocket(`ws://${location.host}/ws`);
    view.ws = ws;
    ws.onopen = () => { view.connected = true; };
    ws.onclose = () => { view.connected = false; setTimeout(connect, 1000); };
    ws.onmessage = (ev) => {
      let m;
      try { m = JSON.parse(ev.data); } catch { return; }
      if (m.type === 'match') setMatch(m);
      else if (m.type === 'frame') {
        view.frame = m; view.frames++; view.frameAt = performance.now();
        if (m.replay) setTimeline(m.replay);
      } else if (m.type === 'timeline') setTimeline(m);
      else if (m.type === 'error') { view.errors++; view.lastError = m.reason; }
    };
  }

  function setMatch(m) {
    view.match = m;
    const replay = m.mode === 'replay';
    $('timeline').hidden = !replay;
    $('help').hidden = replay;
    $('help-replay').hidden = !replay;
    document.body.classList.toggle('replay', replay);
    $('s-self-label').textContent = replay ? 'camera' : 'you';
    view.roster.clear();
    const r = m.roster;
    for (let i = 0; i < r.id.length; i++) {
      view.roster.set(r.id[i], {
        radius: r.radius[i], halfHeight: r.half_height[i], faction: r.faction[i],
        type: m.character_types[r.type[i]] || String(r.type[i]), archetype: m.archetypes[r.archetype[i]] || '?',
      });
    }
  }

  // --- input --------------------------------------------------------------------------------
  function selfPose() {
    const f = view.frame;
    if (!f) return null;
    const o = f.objects;
    if (isReplay()) {  // the followed character, if any
      if (!view.followId) return null;
      for (let i = 0; i < o.length; i += 4) if (o[i] === view.followId) return { x: o[i + 1], y: o[i + 2], yaw: o[i + 3] };
      return null;
    }
    for (let i = 0; i < o.length; i += 4) if (o[i] === f.entity) return { x: o[i + 1], y: o[i + 2], yaw: o[i + 3] };
    return f.self;
  }

  function currentInput() {
    let mx = 0, my = 0;
    for (const k of view.keys) if (MOVE_KEYS[k]) { mx += MOVE_KEYS[k][0]; my += MOVE_KEYS[k][1]; }
    const len = Math.hypot(mx, my);
    if (len > 1) { mx /= len; my /= len; }
    const self = selfPose();
    if (view.aimWithMouse && view.mouse && self) {
      const w = toWorld(view.mouse.x, view.mouse.y);
      if (Math.hypot(w.x - self.x, w.y - self.y) > 0.05) view.facing = Math.atan2(w.y - self.y, w.x - self.x);
    } else if (len > 0) {
      view.facing = Math.atan2(my, mx);
    }
    const shift = view.keys.has('ShiftLeft') || view.keys.has('ShiftRight');
    const msg = {
      type: 'input', move_x: mx, move_y: my, facing: view.facing,
      actions: (shift ? ACTION_SPRINT : 0) | (view.keys.has('Space') ? ACTION_BRACE : 0) |
        (view.showShapes ? ACTION_CONTACTS : 0),
    };
    if (view.panned) { msg.camera_x = view.center.x; msg.camera_y = view.center.y; }
    return msg;
  }

  function send(msg) {
    if (!view.connected || view.ws.readyState !== WebSocket.OPEN) return false;
    view.ws.send(JSON.stringify(msg));
    return true;
  }

  function sendInput() {
    if (!view.match || isReplay()) return;  // a replay has nothing to control
    if (!view.connected || view.ws.readyState !== WebSocket.OPEN) return;
    view.ws.send(JSON.stringify(currentInput()));
    view.sent++;
  }

  addEventListener('keydown', (e) => {
    if (e.ctrlKey || e.metaKey || e.altKey) return;
    if (isReplay()) { replayKey(e); return; }
    if (e.code === 'KeyC' && !e.repeat) setShapes(!view.showShapes);
    if (e.code === 'KeyF') follow();
    if (MOVE_KEYS[e.code] || e.code === 'Space') e.preventDefault();
    if (!view.keys.has(e.code)) { view.keys.add(e.code); sendInput(); }
  });
  addEventListener('keyup', (e) => { view.keys.delete(e.code); sendInput(); });
  addEventListener('blur', () => { view.keys.clear(); sendInput(); });  // no stuck keys
  setInterval(sendInput, 50);  // the gateway stops the character when input goes quiet

  $('shapes').addEventListener('change', (e) => { setShapes(e.target.checked); canvas.focus(); });
  function setShapes(on) {
    view.showShapes = on;
    $('shapes').checked = on;
    if (isReplay()) sendReplayContacts(true);
    else sendInput();  // the contacts bit goes out at once
  }
  // Replay: the viewer picks the pairs around our camera; tell it when the overlay or the camera
  // changes (at most every 200 ms while panning/following).
  function sendReplayContacts(force) {
    if (!isReplay()) return;
    const now = performance.now();
    const on = view.showShapes;
    const last = view.contactsSent;
    const cam = { x: view.center.x, y: view.center.y };
    if (!force) {
      if (!on || (last && last.on && Math.hypot(cam.x - last.x, cam.y - last.y) < 1.0) || (last && now - last.at < 200)) return;
    }
    const msg = on ? { type: 'contacts', on: true, camera_x: cam.x, camera_y: cam.y } : { type: 'contacts', on: false };
    if (send(msg)) view.contactsSent = { on, x: cam.x, y: cam.y, at: now };
  }
  $('follow').addEventListener('click', follow);
  function follow() {  // recentre at once (not only at the next animation frame: a drag may come first)
    view.panned = false;
    const s = selfPose();
    if (s) { view.center.x = s.x; view.center.y = s.y; }
  }

  // --- replay: timeline, play/pause, speed, seek, follow a character -------------------------
  function mmss(ticks, hz) {
    const s = Math.floor(ticks / Math.max(1, hz));
    return `${Math.floor(s / 60)}:${String(s % 60).padStart(2, '0')}`;
  }

  function setTimeline(t) {
    view.replay = t;
    const scrub = $('scrub');
    scrub.max = String(t.last_tick);
    if (!view.scrubbing) scrub.value = String(t.tick);
    $('s-tick').textContent = t.tick;
    $('t-label').textContent = `tick ${t.tick} / ${t.last_tick} · ${mmss(t.tick, t.tick_hz)} / ${mmss(t.last_tick, t.tick_hz)}`;
    $('play').textContent = t.playing ? '❚❚' : '▶';
    const speed = $('speed');
    if (document.activeElement !== speed && Number(speed.value) !== t.speed) speed.value = String(t.speed);
    $('t-state').textContent = t.seeking ? 'seeking…' : (t.at_end && !t.playing ? 'end' : (t.playing ? '' : 'paused'));
  }

  function seekTo(tick, final) {
    const now = performance.now();
    if (!final && now - view.lastSeekSent < 60) return;  // dragging: ~15 seeks a second is plenty
    view.lastSeekSent = now;
    send({ type: 'seek', tick: Number(tick) });
  }

  function setFollow(id) {
    view.followId = id;
    view.panned = !id;
    send({ type: 'focus', id });
  }

  function replayKey(e) {
    const t = view.replay;
    if (e.target && e.target.tagName === 'SELECT') return;
    if (e.code === 'Space') { e.preventDefault(); if (!e.repeat) send({ type: 'toggle' }); }
    else if (e.code === 'KeyC' && !e.repeat) setShapes(!view.showShapes);
    else if (e.code === 'Escape') setFollow(0);
    else if (t && (e.code === 'ArrowLeft' || e.code === 'ArrowRight')) {
      e.preventDefault();
      seekTo(Math.max(0, Math.min(t.last_tick, t.tick + (e.code === 'ArrowLeft' ? -1 : 1) * t.tick_hz)), true);
    }
  }

  $('play').addEventListener('click', () => { send({ type: 'toggle' }); canvas.focus(); });
  $('speed').addEventListener('change', (e) => { send({ type: 'speed', speed: Number(e.target.value) }); canvas.focus(); });
  const scrub = $('scrub');
  scrub.addEventListener('pointerdown', () => { view.scrubbing = true; });
  scrub.addEventListener('input', () => { view.scrubbing = true; seekTo(scrub.value, false); });
  scrub.addEventListener('change', () => { seekTo(scrub.value, true); view.scrubbing = false; canvas.focus(); });
  addEventListener('pointerup', () => { if (view.scrubbing) { seekTo(scrub.value, true); view.scrubbing = false; } });

  // A replay opens on the whole battlefield.
  function fitBounds() {
    const b = view.match.bounds;
    if (!(b[2] > b[0] && b[3] > b[1])) return;
    view.center = { x: (b[0] + b[2]) / 2, y: (b[1] + b[3]) / 2 };
    view.zoom = Math.min(200, Math.max(1, 0.9 * Math.min(canvas.clientWidth / (b[2] - b[0]), canvas.clientHeight / (b[3] - b[1]))));
    view.panned = true;
    view.fitted = true;
  }

  // --- camera: follow, zoom, pan ------------------------------------------------------------
  function toWorld(px, py) {
    return { x: view.center.x + (px - canvas.clientWidth / 2) / view.zoom,
             y: view.center.y - (py - canvas.clientHeight / 2) / view.zoom };
  }

  canvas.addEventListener('wheel', (e) => {
    e.preventDefault();
    const before = toWorld(e.offsetX, e.offsetY);
    view.zoom = Math.min(200, Math.max(1, view.zoom * Math.pow(1.0015, -e.deltaY)));
    if (view.panned) {  // keep the point under the cursor in place
      const after = toWorld(e.offsetX, e.offsetY);
      view.center.x += before.x - after.x;
      view.center.y += before.y - after.y;
    }
  }, { passive: false });
  canvas.addEventListener('mousedown', (e) => {
    if (e.button === 0) view.drag = { x: e.offsetX, y: e.offsetY, moved: false };
    canvas.focus();
  });
  addEventListener('mouseup', (e) => {
    const d = view.drag;
    view.drag = null;
    if (!d || d.moved || !isReplay() || e.target !== canvas) return;
    const c = hovered(view.lastList || [], { x: e.offsetX, y: e.offsetY });
    setFollow(c ? c.id : 0);  // a click on the ground frees the camera
  });
  canvas.addEventListener('mousemove', (e) => {
    view.mouse = { x: e.offsetX, y: e.offsetY };
    view.aimWithMouse = true;
    const d = view.drag;
    if (d && (e.buttons & 1)) {
      const dx = e.offsetX - d.x, dy = e.offsetY - d.y;
      if (d.moved || Math.hypot(dx, dy) > 4) {
        d.moved = true;
        view.panned = true;
        view.center.x -= dx / view.zoom;
        view.center.y += dy / view.zoom;
        d.x = e.offsetX; d.y = e.offsetY;
      }
    }
  });
  canvas.addEventListener('mouseleave', () => { view.mouse = null; view.aimWithMouse = false; });
  canvas.addEventListener('dblclick', follow);

  // --- drawing ------------------------------------------------------------------------------
  function resize() {
    const dpr = window.devicePixelRatio || 1;
    const w = Math.round(canvas.clientWidth * dpr), h = Math.round(canvas.clientHeight * dpr);
    if (canvas.width !== w || canvas.height !== h) { canvas.width = w; canvas.height = h; }
    return dpr;
  }

  function worldTransform(dpr) {
    const z = view.zoom * dpr;
    ctx.setTransform(z, 0, 0, -z, canvas.width / 2 - view.center.x * z, canvas.height / 2 + view.center.y * z);
  }

  function drawScenery(px) {
    for (const s of view.match.scenery) {
      const soft = s.softness > 0;
      ctx.fillStyle = soft ? 'rgba(76, 175, 80, 0.28)' : '#4a5058';
      ctx.strokeStyle = soft ? '#81c784' : '#8a939d';
      ctx.lineWidth = (view.showShapes ? 2 : 1) * px;
      ctx.setLineDash(soft ? [4 * px, 3 * px] : []);
      ctx.beginPath();
      if (s.kind === 'box') {
        ctx.save();
        ctx.translate(s.cx, s.cy);
        ctx.rotate(s.yaw);
        ctx.rect(-s.hx, -s.hy, 2 * s.hx, 2 * s.hy);
        ctx.restore();
        ctx.fill();
        ctx.stroke();
      } else if (s.kind === 'cylinder') {
        ctx.arc(s.cx, s.cy, s.radius, 0, 2 * Math.PI);
        ctx.fill();
        ctx.stroke();
      } else if (s.kind === 'mesh') {  // outline of every triangle, seen from above
        const v = s.vertices, t = s.triangles;
        for (let i = 0; i + 2 < t.length; i += 3) {
          ctx.moveTo(v[3 * t[i]], v[3 * t[i] + 1]);
          ctx.lineTo(v[3 * t[i + 1]], v[3 * t[i + 1] + 1]);
          ctx.lineTo(v[3 * t[i + 2]], v[3 * t[i + 2] + 1]);
          ctx.closePath();
        }
        ctx.stroke();
      }
    }
    ctx.setLineDash([]);
  }

  function drawCharacters(f, px) {
    const o = f.objects;
    const list = [];
    for (let i = 0; i < o.length; i += 4) {
      const info = view.roster.get(o[i]);
      list.push({ id: o[i], x: o[i + 1], y: o[i + 2], yaw: o[i + 3], info, r: info ? info.radius : 0.35 });
    }
    list.sort((a, b) => a.r - b.r);  // mounts and giants over the foot soldiers
    for (const c of list) {
      const faction = c.info ? c.info.faction : 0;
      ctx.beginPath();
      ctx.arc(c.x, c.y, c.r, 0, 2 * Math.PI);
      ctx.fillStyle = FACTION_COLORS[faction % FACTION_COLORS.length];
      ctx.fill();
      ctx.lineWidth = 1 * px;
      ctx.strokeStyle = 'rgba(0, 0, 0, 0.55)';
      ctx.stroke();
      if (c.info && c.info.type === 'mount') {  // a ring marks mounts
        ctx.beginPath();
        ctx.arc(c.x, c.y, c.r * 0.6, 0, 2 * Math.PI);
        ctx.stroke();
      }
      if (c.r * view.zoom > 4) {  // facing tick
        ctx.beginPath();
        ctx.moveTo(c.x, c.y);
        ctx.lineTo(c.x + Math.cos(c.yaw) * c.r, c.y + Math.sin(c.yaw) * c.r);
        ctx.stroke();
      }
      if (c.id === f.entity || (c.id === view.followId && isReplay())) {
        ctx.beginPath();
        ctx.arc(c.x, c.y, c.r + 3 * px, 0, 2 * Math.PI);
        ctx.lineWidth = 3 * px;
        ctx.strokeStyle = '#ffffff';
        ctx.stroke();
      } else if (c.info && c.info.type === 'player') {  // other people's characters
        ctx.beginPath();
        ctx.arc(c.x, c.y, c.r + 1.5 * px, 0, 2 * Math.PI);
        ctx.lineWidth = 1.5 * px;
        ctx.strokeStyle = '#e8eaed';
        ctx.stroke();
      }
      if (view.showShapes) {
        ctx.beginPath();
        ctx.arc(c.x, c.y, c.r, 0, 2 * Math.PI);
        ctx.lineWidth = 1 * px;
        ctx.strokeStyle = '#ffeb3b';
        ctx.stroke();
      }
    }
    return list;
  }

  // Contact planes: for each pair, the line perpendicular to a->b at the point that divides the
  // pair's overlap (or gap) by its push ratio, t = r_a - share_a * (r_a + r_b - d) from a's centre
  // (VP1 of the patent: a was pushed share_a of the depth, b the rest), and the ratio as a/b in %.
  function contactPairs(f) {
    const c = f && f.contacts;
    if (!c || !Array.isArray(c.pairs)) return [];
    const out = [];
    for (let i = 0; i + 4 < c.pairs.length; i += 5)
      out.push({ a: c.pairs[i], b: c.pairs[i + 1], share: c.pairs[i + 2], depth_mm: c.pairs[i + 3], push_mm: c.pairs[i + 4] });
    return out;
  }

  function ratioText(share) {
    const pa = Math.round(share * 100);
    return `${pa}/${100 - pa}`;
  }

  function drawContacts(f, list, px) {
    const drawn = [];
    const pairs = contactPairs(f);
    if (!pairs.length) return drawn;
    const byId = new Map(list.map((c) => [c.id, c]));
    const labels = [];
    for (const p of pairs) {
      const a = byId.get(p.a), b = byId.get(p.b);
      if (!a || !b) continue;  // not drawn here (outside what the page has)
      const dx = b.x - a.x, dy = b.y - a.y, d = Math.hypot(dx, dy);
      if (!(d > 1e-6)) continue;
      const nx = dx / d, ny = dy / d;
      const t = a.r - p.share * (a.r + b.r - d);
      const x = a.x + nx * t, y = a.y + ny * t;
      const half = Math.min(a.r, b.r) * 1.1;
      ctx.beginPath();
      ctx.moveTo(a.x, a.y);
      ctx.lineTo(b.x, b.y);
      ctx.lineWidth = 1 * px;
      ctx.strokeStyle = 'rgba(255, 64, 129, 0.45)';
      ctx.stroke();
      ctx.beginPath();
      ctx.moveTo(x - ny * half, y + nx * half);
      ctx.lineTo(x + ny * half, y - nx * half);
      ctx.lineWidth = 2.5 * px;
      ctx.strokeStyle = PLANE_COLOR;
      ctx.stroke();
      drawn.push({ a: p.a, b: p.b, share: p.share, x, y });
      labels.push({ x, y, text: ratioText(p.share) });
    }
    // Ratios as text in screen space, when there is room for them: nearest the camera first (the
    // order the pairs come in), skipping a label that would overlap one already written.
    if (view.zoom >= 24) {
      ctx.save();
      ctx.setTransform(1, 0, 0, 1, 0, 0);
      const dpr = window.devicePixelRatio || 1;
      ctx.font = `${Math.round(11 * dpr)}px system-ui, sans-serif`;
      ctx.textAlign = 'center';
      ctx.textBaseline = 'middle';
      const placed = [];
      const w = 34 * dpr, h = 14 * dpr;
      for (const l of labels) {
        const sx = (canvas.clientWidth / 2 + (l.x - view.center.x) * view.zoom) * dpr;
        const sy = (canvas.clientHeight / 2 - (l.y - view.center.y) * view.zoom) * dpr;
        if (placed.some((q) => Math.abs(q.x - sx) < w && Math.abs(q.y - sy) < h)) continue;
        placed.push({ x: sx, y: sy });
        ctx.lineWidth = 3 * dpr;
        ctx.strokeStyle = 'rgba(0, 0, 0, 0.75)';
        ctx.strokeText(l.text, sx, sy);
        ctx.fillStyle = '#ffffff';
        ctx.fillText(l.text, sx, sy);
      }
      ctx.restore();
    }
    return drawn;
  }

  function hovered(list, at) {
    const p = at || view.mouse;
    if (!p) return null;
    const w = toWorld(p.x, p.y);
    let best = null, bestD = Infinity;
    for (const c of list) {
      const d = Math.hypot(c.x - w.x, c.y - w.y);
      if (d <= c.r + 2 / view.zoom && d < bestD) { best = c; bestD = d; }
    }
    return best;
  }

  function showTooltip(c) {
    const tip = $('tooltip');
    if (!c) { tip.hidden = true; return; }
    const i = c.info;
    const you = !isReplay() && c.id === view.frame.entity;  // the roster is from match start: it says npc for taken-over bodies
    const p = isReplay() && view.frame.focus && view.frame.focus.id === c.id ? view.frame.focus : null;
    // Its current contact pairs and ratios (what this character moved / what the other moved).
    let ratios = '';
    if (view.showShapes) {
      const mine = contactPairs(view.frame).filter((q) => q.a === c.id || q.b === c.id);
      ratios = mine.length ? '\n' + mine.map((q) => {
        const other = q.a === c.id ? q.b : q.a;
        const share = q.a === c.id ? q.share : 1 - q.share;
        return `vs #${other}: ${ratioText(share)} (moved ${(share * q.push_mm).toFixed(1)} of the pair's ${q.push_mm.toFixed(1)} mm)`;
      }).join('\n') : (view.frame.contacts ? '\nno contact pair near the camera' : '\ncontacts: none from the server');
    }
    tip.textContent = `#${c.id}${you ? ' (you)' : ''}${isReplay() && c.id === view.followId ? ' (followed)' : ''}\n` +
      (i ? `${i.archetype} · ${you ? 'player' : i.type} · faction ${i.faction}\nradius ${i.radius.toFixed(2)} m · half height ${i.halfHeight.toFixed(2)} m\n`
         : 'not in the roster\n') +
      `at (${c.x.toFixed(2)}, ${c.y.toFixed(2)}) facing ${(c.yaw * 180 / Math.PI).toFixed(0)}°\n` +
      (p ? `weight ${p.weight_kg} kg · importance ${p.importance} · equipment ${p.equipment_level}\n` +
           `softness ${p.softness} · speed ${p.speed_mps} m/s · hp ${p.hp} · group ${p.group_id}`
         : (isReplay() ? 'click to follow (and see its parameters)' : '')) + ratios;
    tip.style.left = `${view.mouse.x + 14}px`;
    tip.style.top = `${view.mouse.y + 14}px`;
    tip.hidden = false;
  }

  function draw() {
    const dpr = resize();
    const f = view.frame;
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.fillStyle = BACKGROUND;
    ctx.fillRect(0, 0, canvas.width, canvas.height);
    if (view.match && isReplay() && !view.fitted) fitBounds();
    const self = selfPose();
    if (self && !view.panned) { view.center.x = self.x; view.center.y = self.y; }
    $('follow').hidden = !view.panned || isReplay();
    if (!view.match) { requestAnimationFrame(draw); return; }
    const px = 1 / view.zoom;  // one CSS pixel in metres
    worldTransform(dpr);
    const b = view.match.bounds;
    if (b[2] > b[0] && b[3] > b[1]) {
      ctx.lineWidth = 2 * px;
      ctx.strokeStyle = '#3c4043';
      ctx.strokeRect(b[0], b[1], b[2] - b[0], b[3] - b[1]);
    }
    drawScenery(px);
    let list = [];
    if (f) {
      list = drawCharacters(f, px);
      if (view.showShapes && view.match.interest_radius_m > 0 && f.camera) {  // what the server sends us
        ctx.beginPath();
        ctx.arc(f.camera.x, f.camera.y, view.match.interest_radius_m, 0, 2 * Math.PI);
        ctx.setLineDash([8 * px, 6 * px]);
        ctx.lineWidth = 1.5 * px;
        ctx.strokeStyle = '#80deea';
        ctx.stroke();
        ctx.setLineDash([]);
      }
    }
    view.contactsDrawn = f && view.showShapes ? drawContacts(f, list, px) : [];
    if (view.showShapes) sendReplayContacts(false);
    view.drawn = list.length;
    view.lastList = list;
    view.drawnObjects = f ? f.objects.length / 4 : 0;
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    showTooltip(hovered(list));
    requestAnimationFrame(draw);
  }

  // --- overlay ------------------------------------------------------------------------------
  function updateOverlay() {
    const f = view.frame;
    const status = $('status');
    const ended = (f && f.ended) || (view.match && view.match.ended);
    const stale = f && performance.now() - view.frameAt > 2000;
    let text = isReplay() ? 'replay' : 'live';
    if (!view.connected) text = 'gateway disconnected';
    else if (isReplay()) text = view.replay && view.replay.seeking ? 'replay · seeking…' : 'replay';
    else if (ended) text = 'match ended';
    else if (!f) text = 'waiting for the server…';
    else if (stale) text = 'no snapshots from the server';
    if (view.match && f) text += ` · ${view.match.scene}`;
    status.textContent = text;
    status.className = text.startsWith('live') || text.startsWith('replay') ? '' : 'bad';
    if (!f) return;
    $('s-tick').textContent = f.tick;
    $('contacts-row').hidden = !view.showShapes;
    if (view.showShapes) {
      const c = f.contacts;
      $('s-contacts').textContent = c
        ? `${contactPairs(f).length} pairs (${c.near} near)` + (isReplay() ? '' : ` · ${(f.contacts_kbps || 0).toFixed(1)} kbit/s`)
        : 'waiting…';
    }
    if (isReplay()) {
      $('s-objects').textContent = `${view.drawn} drawn (log: ${f.in_view})`;
      $('s-self').textContent = view.followId ? `following #${view.followId}` : 'free camera';
      return;
    }
    $('s-latency').textContent = f.latency_ms === null ? '–' : `${f.latency_ms.toFixed(0)} ms`;
    $('s-kbps').textContent = `${f.kbps.toFixed(1)} kbit/s`;
    $('s-objects').textContent = `${view.drawn} drawn (server: ${f.in_view})`;
    $('s-self').textContent = f.self
      ? `#${f.entity} (${f.self.x.toFixed(1)}, ${f.self.y.toFixed(1)})${view.panned ? ' · panned' : ''}`
      : '–';
  }
  setInterval(updateOverlay, 250);

  // --- for tests (tests/view/view_e2e_test.cpp) ---------------------------------------------
  window.throngView = {
    stats() {
      const f = view.frame;
      return {
        connected: view.connected, match: !!view.match, frames: view.frames,
        drawn: view.drawn, objects: view.drawnObjects,
        tick: f ? f.tick : null, entity: f ? f.entity : null, self: f ? f.self : null, client_id: f ? f.client_id : null,
        in_view: f ? f.in_view : null, latency_ms: f ? f.latency_ms : null, kbps: f ? f.kbps : null,
        sent: view.sent, errors: view.errors, last_error: view.lastError, panned: view.panned,
        camera: f ? f.camera : null, zoom: view.zoom, show_shapes: view.showShapes,
        tooltip: $('tooltip').hidden ? null : $('tooltip').textContent,
        mode: view.match ? (view.match.mode || 'live') : null, replay: view.replay, follow: view.followId,
        status: $('status').textContent, timeline: $('timeline').hidden ? null : $('t-label').textContent,
        focus: f ? (f.focus || null) : null,
        contacts: f && f.contacts ? { tick: f.contacts.tick, near: f.contacts.near, pairs: contactPairs(f).length,
                                      camera: f.contacts.camera, radius: f.contacts.radius } : null,
        contacts_kbps: f ? (f.contacts_kbps || 0) : null, contacts_drawn: view.contactsDrawn.length,
      };
    },
    // The contact pairs of the newest frame: {a, b, share} (share = the fraction a moved), and
    // which of them the last draw placed a plane for.
    contacts() {
      const drawn = new Set(view.contactsDrawn.map((d) => `${d.a}:${d.b}`));
      return contactPairs(view.frame).map((p) => ({ a: p.a, b: p.b, share: p.share, drawn: drawn.has(`${p.a}:${p.b}`) }));
    },
    // Canvas pixels painted in the contact-plane colour.
    planePixels() {
      const c = [1, 3, 5].map((k) => parseInt(PLANE_COLOR.substr(k, 2), 16));
      const d = ctx.getImageData(0, 0, canvas.width, canvas.height).data;
      let n = 0;
      for (let i = 0; i < d.length; i += 4) if (d[i] === c[0] && d[i + 1] === c[1] && d[i + 2] === c[2]) n++;
      return n;
    },
    // Where a body of the newest frame is on the page, in CSS pixels (for clicking it).
    screenOf(id) {
      const p = this.positions()[id];
      if (!p) return null;
      return { x: canvas.clientWidth / 2 + (p[0] - view.center.x) * view.zoom,
               y: canvas.clientHeight / 2 - (p[1] - view.center.y) * view.zoom };
    },
    // The newest frame's bodies as {id: [x, y]} (replay: every body of the re-simulated world).
    positions() {
      const f = view.frame, out = {};
      if (!f) return out;
      for (let i = 0; i < f.objects.length; i += 4) out[f.objects[i]] = [f.objects[i + 1], f.objects[i + 2]];
      return out;
    },
    // Canvas pixels painted in a faction colour (fills are drawn in exactly these colours).
    factionPixels() {
      const colors = FACTION_COLORS.map((c) => [1, 3, 5].map((k) => parseInt(c.substr(k, 2), 16)));
      const d = ctx.getImageData(0, 0, canvas.width, canvas.height).data;
      let n = 0;
      for (let i = 0; i < d.length; i += 4) {
        for (const c of colors) if (d[i] === c[0] && d[i + 1] === c[1] && d[i + 2] === c[2]) { n++; break; }
      }
      return n;
    },
  };

  connect();
  requestAnimationFrame(draw);
})();
