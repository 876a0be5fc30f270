// SyROF viewer: draws the run embedded in this page (the JSON in
// #syrof-data, written by lab/view from what the replay reader accepted).
// Plain browser JavaScript, no library, no network: the page must work from
// file:// years from now. docs/viewer.md describes what it shows.
//
// URL fragment (for links and for the browser test):
//   #round=N      open at radio round N (the replay's round number)
//   &robot=R      inspect robot R
//   &live-until=rounds:N | crash:R   (live page) stop following the stream
//                 once N rounds are drawn, or robot R is drawn crashed: the
//                 browser test's headless Chromium dumps the page then
// When the page is ready, <body data-ready="1"> and #report holds a JSON
// summary of what is drawn (robots, marks, inspector), which the browser
// test compares with the replay.
//
// Live mode (docs/viewer.md, "Live"): when the data says `live`, the page
// holds no run yet; it connects to the server's /events stream, gets the
// run's header, then its rounds as they are recorded, appends them, follows
// the newest round unless the user went back, and at the end says the run
// ended and links the replay's page. #report is then refreshed at every
// update, with a `live` part (rounds held, newest round, whether it ended,
// when each robot was first drawn crashed).
'use strict';

(function () {
  const scriptStart = performance.now();
  const COLOURS = {
    cooperative: [47, 127, 208],
    autonomous: [232, 134, 42],
    joining: [142, 108, 199],
    paused: [185, 190, 200],
    crashed: [75, 81, 96],
    fault: [208, 40, 40],
    collision: [208, 40, 40],
    safety: [230, 180, 0],
    lost: [194, 24, 91],
    wall: [120, 124, 135],
    target: [31, 138, 76],
    starting: [168, 186, 210],
  };
  // world::RobotKind by value, as the replay stores it.
  const KIND_NAMES = ['omni', 'rover', 'drone'];
  const KIND_COLOURS = {
    EPOCH_START: '#9aa3b5', MEMBER_REMOVED: '#d0452f', MEMBER_JOINED: '#2e9d5b', BECAME_JOINER: '#8e6cc7',
    COLLISION: '#d02828', WALL_CONTACT: '#a0522d', CRASH: '#4b5160', PAUSE: '#7d8699', RESUME: '#2e9d5b',
    JOIN: '#8e6cc7', PARTITION_START: '#c2185b', PARTITION_END: '#c2185b', APP_FAULT: '#d02828',
    INVALID_COMMAND: '#e8862a', PAYLOAD_REFUSED: '#e8862a', SAFETY_INTERVENTION: '#e6b400', JOIN_WAIT: '#8e6cc7',
    BEACON_LOST: '#c2185b',
  };
  const PRESENCE = ['ABSENT', 'RUNNING', 'PAUSED', 'CRASHED'];
  const PHASES = ['PROGRESS', 'WAIT', 'VOTE'];
  const MODES = ['COOPERATIVE', 'AUTONOMOUS'];
  const MARK_ROUNDS = 20;  // a collision or intervention stays marked this many rounds
  const TRAIL_SAMPLES = 40;

  const rgb = (c, a) => (a === undefined ? `rgb(${c[0]},${c[1]},${c[2]})` : `rgba(${c[0]},${c[1]},${c[2]},${a})`);
  const $ = (id) => document.getElementById(id);
  const el = (tag, props, children) => {
    const node = document.createElement(tag);
    if (props) Object.assign(node, props);
    for (const child of children || []) node.append(child);
    return node;
  };
  const undelta = (list) => {
    const out = new Float64Array(list.length);
    let value = 0;
    for (let i = 0; i < list.length; ++i) { value += list[i]; out[i] = value; }
    return out;
  };
  const fmt = (value, digits) => (Number.isFinite(value) ? value.toFixed(digits) : '-');

  // ---- Data -----------------------------------------------------------------
  let data;
  try {
    data = JSON.parse($('syrof-data').textContent);
  } catch (error) {
    data = { status: 'invalid', message: 'The page\'s data cannot be read: ' + error };
  }

  function showBanner(kind, title, text, fatal) {
    const banner = $('banner');
    banner.hidden = false;
    banner.className = kind + (fatal ? ' fatal' : '');
    banner.replaceChildren(el('h2', { textContent: title }), el('div', { textContent: text }));
  }

  // The run's verdict, first on the page (docs/viewer.md, "The verdict"):
  // lab/view wrote its words; the page only lays them out.
  function showVerdict() {
    const v = data.verdict;
    const box = $('verdict');
    if (!v || live) { box.hidden = true; return null; }
    box.hidden = false;
    box.className = v.state;
    const lines = v.lines.map(([topic, ok, text]) => el('li', { className: ok ? 'ok' : 'bad' }, [el('b', { textContent: topic }), text]));
    box.replaceChildren(el('div', { className: 'headline', textContent: v.headline }), el('ul', {}, lines));
    return { state: v.state, headline: v.headline };
  }

  function finish(report) {
    report.status = data.status;
    report.ready_ms = Math.round(performance.now());  // since navigation start
    report.script_ms = Math.round(performance.now() - scriptStart);  // parsing the data and the first drawing
    $('report').textContent = JSON.stringify(report);
    document.body.dataset.ready = '1';
  }

  // ---- Live: wait for the header, then start as for a file -------------------
  const LIVE_MAX_ROUNDS = 12000;  // what the page holds: 10 min of 50 ms rounds
  let live = null;
  if (data.live) {
    live = { source: null, ended: null, skipped: 0, updated: 0, pending: [], crashShown: {}, lastWallUs: null, started: false };
    showBanner('live', 'Live', 'Connecting to the run…');
    $('banner').className = 'live';
    $('app').hidden = true;
    $('plots').hidden = true;
    const source = new EventSource(data.live.events);
    live.source = source;
    source.addEventListener('header', (ev) => {
      if (live.started) return;  // a reconnect sends it again
      const header = JSON.parse(ev.data);
      data = Object.assign(header, { status: 'live', live: data.live, stride: 1,
                                     rounds: { index: [], time_us: [] }, frames: header.robots.map(() => ({ s: [], e: [], x: [], y: [], h: [], ex: [], ey: [], eh: [] })),
                                     events: [], maps: [], starts: [] });
      live.started = true;
      $('app').hidden = false;
      $('plots').hidden = false;
      start();
    });
    // Drawn at most every 100 ms of the recording's own clock (`w`, when the
    // server recorded the round), not the browser's: a page whose timers are
    // held back (a background tab, headless Chromium's virtual time) still
    // draws as the rounds come; a timer draws what came after.
    source.addEventListener('round', (ev) => {
      const r = JSON.parse(ev.data);
      live.pending.push(r);
      if (!live.update) return;
      if (r.w - (live.drawnW || 0) >= 100000) live.updateNow(); else live.update();
    });
    source.addEventListener('skipped', (ev) => { live.skipped += JSON.parse(ev.data).rounds; });
    source.addEventListener('end', (ev) => { live.ended = JSON.parse(ev.data); source.close(); if (live.update) live.update(); });
    source.onerror = () => {
      if (!live.ended && !live.started) showBanner('live', 'Live', 'Waiting for the run\'s server (it may have ended)…');
    };
    finish({ robots_drawn: 0, live: { rounds: 0 } });
    return;
  }
  start();

  function start() {
  const TITLES = {
    empty: 'Nothing to show', truncated: 'This replay is cut short', invalid: 'This replay is damaged',
    newer: 'This replay is from a newer SyROF',
  };
  if (data.data_version !== 1 || !data.frames) {
    $('app').hidden = true;
    $('plots').hidden = true;
    showBanner(data.status || 'invalid', TITLES[data.status] || 'Nothing to show',
               data.message || 'This page holds no run.', true);
    finish({ robots_drawn: 0 });
    return;
  }
  if (data.status !== 'complete' && !live) {
    showBanner(data.status, TITLES[data.status] || 'Problem', data.message || '', data.status === 'empty');
  }
  const verdictShown = showVerdict();

  const timings = { parse_ms: Math.round(performance.now() - scriptStart) };
  const robots = data.robots;
  const stride = data.stride;
  const kinds = data.kinds;
  const slotOf = new Map(robots.map((r, i) => [r.id, i]));
  // The run's rounds as the page draws them: from the file's columns once,
  // or (live) from the rounds received so far, again at each update.
  let roundIndex, roundTime, rounds, samples, frames, events, startsOf, faultedFrom, leftOut;
  function deriveRounds() {
    if (live) {
      roundIndex = data.rounds.index;
      roundTime = data.rounds.time_us;
      frames = data.frames;
    } else {
      roundIndex = undelta(data.rounds.index);
      roundTime = undelta(data.rounds.time_us);  // microseconds
      frames = data.frames.map((f) => ({
        s: f.s, e: undelta(f.e), x: undelta(f.x), y: undelta(f.y), h: undelta(f.h),
        ex: undelta(f.ex), ey: undelta(f.ey), eh: undelta(f.eh),
      }));
    }
    rounds = roundIndex.length;
    samples = rounds === 0 ? 0 : Math.floor((rounds - 1) / stride) + 1;
    events = data.events.map((e, n) => ({
      n, pos: e[0], kind: kinds[e[1]] || ('kind ' + e[1]), robot: e[2], other: e[3], epoch: e[4], mode: e[5],
      t: e[6] / 1e6, partition: e[7],
    }));
    // Per robot: its epoch starts in order, with the map each began with.
    // Under SSYNC a start's fourth field is 0 when the schedule left its
    // robot out of that epoch; under ASYNC it is 0 when the robot did not
    // look (a cycle under way), and the start also carries the epoch of the
    // look its move comes from, whether it moves and whether the move is
    // cut (docs/activation.md).
    startsOf = robots.map(() => []);
    leftOut = new Map();
    for (const [pos, robot, map, active, lookEpoch, moves, cut] of data.starts) {
      const slot = slotOf.get(robot);
      const start = { pos, map, active: active !== 0, lookEpoch, moves: moves === 1, cut: cut === 1 };
      if (slot !== undefined) startsOf[slot].push(start);
      if (active === 0) leftOut.set(pos + ':' + robot, start);
    }
    // Robots whose app faulted, from which round position.
    faultedFrom = new Map();
    for (const e of events) if (e.kind === 'APP_FAULT' && !faultedFrom.has(e.robot)) faultedFrom.set(e.robot, e.pos);
  }
  deriveRounds();

  const state = (slot, sample) => frames[slot].s[sample];
  const presenceOf = (s) => s & 3;
  const joiningOf = (s) => (s >> 2) & 1;
  const phaseOf = (s) => (s >> 3) & 3;
  const modeOf = (s) => (s >> 5) & 1;
  const sampleOf = (pos) => Math.min(samples - 1, Math.floor(pos / stride));
  const timeOf = (pos) => roundTime[Math.max(0, Math.min(rounds - 1, pos))] / 1e6;

  function robotColour(s, slot, pos) {
    const presence = presenceOf(s);
    if (presence === 3) return faultedFrom.has(robots[slot].id) && faultedFrom.get(robots[slot].id) <= pos ? COLOURS.fault : COLOURS.crashed;
    if (presence === 2) return COLOURS.paused;
    if (joiningOf(s)) return COLOURS.joining;
    if (frames[slot].e[sampleOf(pos)] === 0) return COLOURS.starting;  // no epoch yet: no mode either
    return modeOf(s) === 0 ? COLOURS.cooperative : COLOURS.autonomous;
  }

  // ---- Header -----------------------------------------------------------------
  $('run-name').textContent = `${data.scenario} · ${data.app} · seed ${data.seed}`;
  let duration = 0;
  function runFacts() {
    duration = rounds ? timeOf(rounds - 1) : 0;
    $('run-facts').textContent = `${robots.length} robots · ${rounds} radio rounds of ${data.round_ns / 1e6} ms · ` +
        `${fmt(duration, 1)} s · ${events.length} events · arena ${data.arena[0]} × ${data.arena[1]} m · replay v${data.replay_version}` +
        (stride > 1 ? ` · frames drawn every ${stride} rounds` : '') + (live ? ' · live' : '');
  }
  runFacts();
  document.title = `SyROF ${live ? 'live' : 'viewer'}: ${data.scenario} (seed ${data.seed})`;

  // ---- Current position -------------------------------------------------------
  let pos = 0;          // round position (0 .. rounds-1)
  let selected = -1;    // robot slot
  let playing = false;
  let speed = 1;
  let lastReport = {};

  // ---- Arena --------------------------------------------------------------------
  const arena = $('arena');
  const actx = arena.getContext('2d');
  let view = { ox: 0, oy: 0, scale: 1 };

  function layoutArena() {
    const box = $('arena-box');
    const width = Math.max(300, box.clientWidth);
    const aspect = data.arena[1] / data.arena[0];
    let w = width;
    let h = Math.round(w * aspect);
    // Never taller than 640 px: a bigger arena is no easier to read, and the
    // controls stay on a laptop's screen. Not tied to the window's height,
    // which a screenshot and a DOM dump of the same window do not agree on.
    const maxH = 640;
    if (h > maxH) { h = Math.round(maxH); w = Math.round(h / aspect); }
    const ratio = window.devicePixelRatio || 1;
    arena.style.width = w + 'px';
    arena.style.height = h + 'px';
    arena.width = Math.round(w * ratio);
    arena.height = Math.round(h * ratio);
    actx.setTransform(ratio, 0, 0, ratio, 0, 0);
    const margin = 16;
    const scale = Math.min((w - 2 * margin) / data.arena[0], (h - 2 * margin) / data.arena[1]);
    view = { w, h, scale, ox: (w - scale * data.arena[0]) / 2, oy: h - (h - scale * data.arena[1]) / 2 };
  }
  const sx = (x) => view.ox + x * view.scale;
  const sy = (y) => view.oy - y * view.scale;

  function drawArena() {
    const ctx = actx;
    ctx.clearRect(0, 0, view.w, view.h);
    // Floor grid every metre (every 5 m in big arenas), walls, anchors.
    const step = data.arena[0] > 20 ? 5 : 1;
    ctx.strokeStyle = '#eceef2';
    ctx.lineWidth = 1;
    ctx.beginPath();
    for (let x = step; x < data.arena[0]; x += step) { ctx.moveTo(sx(x), sy(0)); ctx.lineTo(sx(x), sy(data.arena[1])); }
    for (let y = step; y < data.arena[1]; y += step) { ctx.moveTo(sx(0), sy(y)); ctx.lineTo(sx(data.arena[0]), sy(y)); }
    ctx.stroke();
    ctx.strokeStyle = rgb(COLOURS.wall);
    ctx.lineWidth = 3;
    ctx.strokeRect(sx(0), sy(data.arena[1]), data.arena[0] * view.scale, data.arena[1] * view.scale);
    for (const [x, y] of data.anchors) {
      const px = sx(x), py = sy(y);
      ctx.fillStyle = '#1d2330';
      ctx.beginPath();
      ctx.moveTo(px, py - 7); ctx.lineTo(px + 6, py + 5); ctx.lineTo(px - 6, py + 5); ctx.closePath();
      ctx.fill();
    }
    if (rounds === 0) return { robots_drawn: 0, marks: [], targets: [], labels: [] };

    const sample = sampleOf(pos);
    const targetsDrawn = drawTargets(ctx, sample);
    const many = robots.length > 30;
    // Trails.
    ctx.lineWidth = 1.5;
    for (let slot = 0; slot < robots.length; ++slot) {
      const f = frames[slot];
      const from = Math.max(0, sample - TRAIL_SAMPLES);
      if (presenceOf(f.s[sample]) === 0) continue;
      ctx.strokeStyle = rgb(robotColour(f.s[sample], slot, pos), 0.35);
      ctx.beginPath();
      let started = false;
      for (let i = from; i <= sample; ++i) {
        if (presenceOf(f.s[i]) === 0) { started = false; continue; }
        const px = sx(f.x[i] / 1000), py = sy(f.y[i] / 1000);
        if (started) ctx.lineTo(px, py); else ctx.moveTo(px, py);
        started = true;
      }
      ctx.stroke();
    }
    // Estimated poses as ghosts, under the bodies.
    for (let slot = 0; slot < robots.length; ++slot) {
      const f = frames[slot];
      const s = f.s[sample];
      if (presenceOf(s) === 0) continue;
      const r = Math.max(3, robots[slot].radius * view.scale);
      const tx = sx(f.x[sample] / 1000), ty = sy(f.y[sample] / 1000);
      const ex = sx(f.ex[sample] / 1000), ey = sy(f.ey[sample] / 1000);
      ctx.strokeStyle = rgb(robotColour(s, slot, pos), 0.7);
      ctx.setLineDash([3, 3]);
      ctx.lineWidth = 1;
      ctx.beginPath(); ctx.arc(ex, ey, r, 0, 2 * Math.PI); ctx.stroke();
      ctx.setLineDash([]);
      ctx.beginPath(); ctx.moveTo(tx, ty); ctx.lineTo(ex, ey); ctx.stroke();
    }
    // Bodies.
    let drawn = 0;
    const leftOutDrawn = [];
    const labels = [];
    for (let slot = 0; slot < robots.length; ++slot) {
      const f = frames[slot];
      const s = f.s[sample];
      const presence = presenceOf(s);
      if (presence === 0) continue;
      ++drawn;
      const r = Math.max(3, robots[slot].radius * view.scale);
      const px = sx(f.x[sample] / 1000), py = sy(f.y[sample] / 1000);
      const heading = f.h[sample] / 1000;
      const colour = robotColour(s, slot, pos);
      ctx.fillStyle = rgb(colour);
      ctx.beginPath(); ctx.arc(px, py, r, 0, 2 * Math.PI); ctx.fill();
      ctx.lineWidth = slot === selected ? 3 : 1;
      ctx.strokeStyle = slot === selected ? '#111' : 'rgba(0,0,0,0.35)';
      ctx.stroke();
      if (robots[slot].kind === 2) {
        // A drone: four rotors, rings on the diagonals joined by arms.
        ctx.strokeStyle = 'rgba(0,0,0,0.55)';
        ctx.lineWidth = 1;
        const arm = r * 0.62, rotor = Math.max(1.5, r * 0.32);
        for (let k = 0; k < 4; ++k) {
          const a = heading + Math.PI / 4 + k * Math.PI / 2;
          const qx = px + Math.cos(a) * arm, qy = py - Math.sin(a) * arm;
          ctx.beginPath(); ctx.moveTo(px, py); ctx.lineTo(qx, qy); ctx.stroke();
          ctx.beginPath(); ctx.arc(qx, qy, rotor, 0, 2 * Math.PI); ctx.stroke();
        }
      }
      if (joiningOf(s) && presence === 1) {
        ctx.setLineDash([4, 3]); ctx.strokeStyle = rgb(COLOURS.joining); ctx.lineWidth = 2;
        ctx.beginPath(); ctx.arc(px, py, r + 4, 0, 2 * Math.PI); ctx.stroke(); ctx.setLineDash([]);
      } else if (presence === 1 && leftOutAt(slot, pos)) {
        // Left out of this epoch by the SSYNC schedule: it holds its place.
        leftOutDrawn.push(robots[slot].id);
        ctx.setLineDash([2, 3]); ctx.strokeStyle = '#5b6272'; ctx.lineWidth = 2;
        ctx.beginPath(); ctx.arc(px, py, r + 4, 0, 2 * Math.PI); ctx.stroke(); ctx.setLineDash([]);
      }
      // Heading: a white line from the centre to the rim (rovers: a wedge).
      ctx.strokeStyle = '#fff';
      ctx.lineWidth = Math.max(1.5, r / 6);
      ctx.beginPath(); ctx.moveTo(px, py);
      ctx.lineTo(px + Math.cos(heading) * r * 0.95, py - Math.sin(heading) * r * 0.95); ctx.stroke();
      if (presence === 3) {
        ctx.strokeStyle = faultedFrom.has(robots[slot].id) ? '#fff' : '#e3e5ea';
        ctx.lineWidth = 2;
        const d = r * 0.55;
        ctx.beginPath(); ctx.moveTo(px - d, py - d); ctx.lineTo(px + d, py + d);
        ctx.moveTo(px + d, py - d); ctx.lineTo(px - d, py + d); ctx.stroke();
      } else if (presence === 2) {
        ctx.fillStyle = '#4b5160';
        ctx.fillRect(px - r * 0.4, py - r * 0.45, r * 0.25, r * 0.9);
        ctx.fillRect(px + r * 0.15, py - r * 0.45, r * 0.25, r * 0.9);
      }
      if (!many || slot === selected) {
        ctx.fillStyle = '#1d2330';
        ctx.font = '600 11px system-ui, sans-serif';
        ctx.fillText(String(robots[slot].id), px + r * 0.75 + 2, py - r * 0.75 - 2);
        if (presence === 1) {
          const label = stateLabel(s, f.e[sample]);
          ctx.fillStyle = '#667085';
          ctx.font = '10px system-ui, sans-serif';
          ctx.fillText(label, px + r * 0.75 + 2, py + r + 9);
          labels.push({ robot: robots[slot].id, label, colour });
        }
      }
    }
    // Marks: collisions, wall contacts, safety interventions and lost
    // beacons of the last MARK_ROUNDS rounds, where they happened.
    const marks = [];
    const first = lowerBound(pos - MARK_ROUNDS + 1);
    for (let n = first; n < events.length && events[n].pos <= pos; ++n) {
      const e = events[n];
      if (e.kind !== 'COLLISION' && e.kind !== 'SAFETY_INTERVENTION' && e.kind !== 'WALL_CONTACT' &&
          e.kind !== 'BEACON_LOST') continue;
      const a = slotOf.get(e.robot);
      if (a === undefined) continue;
      const b = e.other >= 0 ? slotOf.get(e.other) : undefined;
      const es = sampleOf(e.pos);
      if (e.kind === 'BEACON_LOST') {
        // A dashed arrow from the sender to the receiver that did not hear
        // it, crossed out halfway.
        if (b === undefined) continue;
        const fade = 1 - (pos - e.pos) / MARK_ROUNDS;
        const x0 = sx(frames[a].x[es] / 1000), y0 = sy(frames[a].y[es] / 1000);
        const x1 = sx(frames[b].x[es] / 1000), y1 = sy(frames[b].y[es] / 1000);
        const len = Math.hypot(x1 - x0, y1 - y0) || 1, ux = (x1 - x0) / len, uy = (y1 - y0) / len;
        const rb = Math.max(6, robots[b].radius * view.scale);
        const tx = x1 - ux * rb, ty = y1 - uy * rb;
        ctx.strokeStyle = rgb(COLOURS.lost, fade);
        ctx.lineWidth = 2;
        ctx.setLineDash([6, 4]);
        ctx.beginPath(); ctx.moveTo(x0, y0); ctx.lineTo(tx, ty); ctx.stroke();
        ctx.setLineDash([]);
        ctx.beginPath();
        ctx.moveTo(tx, ty); ctx.lineTo(tx - ux * 9 - uy * 5, ty - uy * 9 + ux * 5);
        ctx.moveTo(tx, ty); ctx.lineTo(tx - ux * 9 + uy * 5, ty - uy * 9 - ux * 5);
        const mx = (x0 + tx) / 2, my = (y0 + ty) / 2;
        ctx.moveTo(mx - 6, my - 6); ctx.lineTo(mx + 6, my + 6);
        ctx.moveTo(mx - 6, my + 6); ctx.lineTo(mx + 6, my - 6);
        ctx.stroke();
        marks.push({ kind: e.kind, robot: e.robot, other: e.other, round: roundIndex[e.pos] });
        continue;
      }
      let mx = frames[a].x[es] / 1000, my = frames[a].y[es] / 1000;
      if (b !== undefined && e.kind === 'COLLISION') {
        mx = (mx + frames[b].x[es] / 1000) / 2; my = (my + frames[b].y[es] / 1000) / 2;
      }
      const fade = 1 - (pos - e.pos) / MARK_ROUNDS;
      const px = sx(mx), py = sy(my);
      if (e.kind === 'SAFETY_INTERVENTION') {
        ctx.fillStyle = rgb(COLOURS.safety, 0.9 * fade);
        ctx.beginPath(); ctx.moveTo(px, py - 14); ctx.lineTo(px + 8, py - 2); ctx.lineTo(px - 8, py - 2); ctx.closePath(); ctx.fill();
      } else {
        ctx.strokeStyle = rgb(COLOURS.collision, fade);
        ctx.lineWidth = 3;
        const r = Math.max(10, robots[a].radius * view.scale * 1.6);
        ctx.beginPath(); ctx.arc(px, py, r, 0, 2 * Math.PI); ctx.stroke();
        for (let k = 0; k < 8; ++k) {
          const ang = k * Math.PI / 4;
          ctx.beginPath();
          ctx.moveTo(px + Math.cos(ang) * (r + 3), py + Math.sin(ang) * (r + 3));
          ctx.lineTo(px + Math.cos(ang) * (r + 9), py + Math.sin(ang) * (r + 9));
          ctx.stroke();
        }
      }
      marks.push({ kind: e.kind, robot: e.robot, other: e.other, round: roundIndex[e.pos] });
    }
    return { robots_drawn: drawn, marks, targets: targetsDrawn, labels, left_out: leftOutDrawn };
  }

  // The goal's target (lab/view's GoalTargets), under everything else: a
  // ring or an annulus (centred where the robots are when the goal leaves
  // the centre free), slots with their tolerance, a coverage area.
  function drawTargets(ctx, sample) {
    const drawn = [];
    const c = COLOURS.target;
    for (const t of data.targets || []) {
      if (t.shape === 'ring' || t.shape === 'free_ring') {
        let x = t.x, y = t.y;
        if (t.shape === 'free_ring') {
          let n = 0; x = 0; y = 0;
          for (let slot = 0; slot < robots.length; ++slot) {
            const f = frames[slot];
            const presence = presenceOf(f.s[sample]);
            if (presence !== 1 && presence !== 2) continue;
            x += f.x[sample] / 1000; y += f.y[sample] / 1000; ++n;
          }
          if (n === 0) continue;
          x /= n; y /= n;
        }
        const px = sx(x), py = sy(y), r0 = t.r_min * view.scale, r1 = t.r_max * view.scale;
        ctx.fillStyle = rgb(c, 0.10);
        ctx.beginPath();
        ctx.arc(px, py, r1, 0, 2 * Math.PI);
        if (r1 - r0 > 1) { ctx.moveTo(px + r0, py); ctx.arc(px, py, r0, 0, 2 * Math.PI, true); }
        ctx.fill('evenodd');
        ctx.strokeStyle = rgb(c, 0.85);
        ctx.lineWidth = 2;
        ctx.setLineDash(t.shape === 'free_ring' ? [8, 5] : []);
        ctx.beginPath(); ctx.arc(px, py, r1, 0, 2 * Math.PI); ctx.stroke();
        if (r1 - r0 > 1) { ctx.beginPath(); ctx.arc(px, py, r0, 0, 2 * Math.PI); ctx.stroke(); }
        ctx.setLineDash([]);
        ctx.lineWidth = 1.5;
        ctx.beginPath(); ctx.moveTo(px - 6, py); ctx.lineTo(px + 6, py); ctx.moveTo(px, py - 6); ctx.lineTo(px, py + 6); ctx.stroke();
        drawn.push({ shape: t.shape, name: t.name, x, y, r_min: t.r_min, r_max: t.r_max });
      } else if (t.shape === 'points') {
        const r = Math.max(4, t.r * view.scale);
        for (const [x, y, id] of t.points) {
          const px = sx(x), py = sy(y);
          ctx.fillStyle = rgb(c, 0.14);
          ctx.strokeStyle = rgb(c, 0.85);
          ctx.lineWidth = 1.5;
          ctx.beginPath(); ctx.arc(px, py, r, 0, 2 * Math.PI); ctx.fill(); ctx.stroke();
          ctx.beginPath(); ctx.moveTo(px - 4, py); ctx.lineTo(px + 4, py); ctx.moveTo(px, py - 4); ctx.lineTo(px, py + 4); ctx.stroke();
          if (id >= 0) {
            ctx.fillStyle = rgb(c);
            ctx.font = '600 10px system-ui, sans-serif';
            ctx.fillText(String(id), px - r * 0.7 - 8, py - r * 0.7 - 2);
          }
        }
        drawn.push({ shape: t.shape, name: t.name, points: t.points.length, r: t.r });
      } else if (t.shape === 'rect') {
        const x = sx(Math.min(t.x0, t.x1)), y = sy(Math.max(t.y0, t.y1));
        const w = Math.abs(t.x1 - t.x0) * view.scale, h = Math.abs(t.y1 - t.y0) * view.scale;
        ctx.fillStyle = rgb(c, 0.08);
        ctx.fillRect(x, y, w, h);
        ctx.strokeStyle = rgb(c, 0.85);
        ctx.lineWidth = 2;
        ctx.setLineDash([8, 5]);
        ctx.strokeRect(x, y, w, h);
        ctx.setLineDash([]);
        drawn.push({ shape: t.shape, name: t.name });
      }
    }
    return drawn;
  }

  // A running robot's label under its body: its phase's initial and its
  // epoch; "joining" while it is not a member, "starting" before its first
  // epoch (epoch 0: it has not started one, so no phase means anything yet).
  function stateLabel(s, epoch) {
    if (joiningOf(s)) return 'joining';
    if (epoch === 0) return 'starting';
    return PHASES[phaseOf(s)][0] + ' ' + epoch;
  }

  // First event at or after round position `p`.
  // The robot's latest epoch start at or before position p, if the schedule
  // left it out of that epoch.
  function leftOutAt(slot, p) {
    let latest = null;
    for (const start of startsOf[slot]) { if (start.pos <= p) latest = start; else break; }
    return latest !== null && !latest.active;
  }

  function lowerBound(p) {
    let lo = 0, hi = events.length;
    while (lo < hi) { const mid = (lo + hi) >> 1; if (events[mid].pos < p) lo = mid + 1; else hi = mid; }
    return lo;
  }

  function legend() {
    const items = [['COOPERATIVE', COLOURS.cooperative], ['AUTONOMOUS', COLOURS.autonomous], ['joining', COLOURS.joining],
                   ['paused', COLOURS.paused], ['crashed', COLOURS.crashed], ['app fault', COLOURS.fault],
                   ['starting (no epoch yet)', COLOURS.starting]];
    const nodes = items.map(([name, c]) => el('span', {}, [el('i', { className: 'sw', style: `background:${rgb(c)};margin:0` }), name]));
    nodes.push(el('span', { textContent: '◌ dashed: the robot\'s own estimate' }));
    if (data.activation && data.activation.model === 'async') {
      nodes.push(el('span', { textContent: `⋯ dotted ring: did not look this epoch (ASYNC, ${data.activation.schedule}): moving on an older look, or waiting to move` }));
    } else if (data.activation) {
      nodes.push(el('span', { textContent: `⋯ dotted ring: left out of this epoch (${data.activation.model.toUpperCase()}, ${data.activation.schedule})` }));
    }
    nodes.push(el('span', { innerHTML: '<b style="color:#d02828">◎</b> collision' }));
    nodes.push(el('span', { innerHTML: '<b style="color:#e6b400">▲</b> safety intervention' }));
    if (events.some((e) => e.kind === 'BEACON_LOST')) {
      nodes.push(el('span', { innerHTML: '<b style="color:#c2185b">⇢✕</b> lost beacon (scripted)' }));
    }
    const targets = data.targets || [];
    const drawnTargets = targets.filter((t) => t.shape !== 'none');
    if (drawnTargets.length) {
      const names = [...new Set(drawnTargets.map((t) => t.name))].join(', ');
      const free = drawnTargets.some((t) => t.shape === 'free_ring') ? ' (dashed: centre free, drawn at the robots\' centre)' : '';
      nodes.push(el('span', {}, [el('b', { textContent: '◎', style: `color:${rgb(COLOURS.target)}` }), `goal target: ${names}${free}`]));
    }
    for (const t of targets.filter((t) => t.shape === 'none')) nodes.push(el('span', { textContent: `goal ${t.name}: not drawn, ${t.why}` }));
    nodes.push(el('span', { textContent: '▲ UWB anchor · label: id, phase (P, W, V) and epoch, or starting' }));
    $('legend').replaceChildren(...nodes);
  }

  // ---- Inspector ----------------------------------------------------------------
  // What only this robot knew (syrofAppInput): "charge 870".
  function privateInputs(robot) {
    if (data.replay_version < 4) return `not recorded (replay format version ${data.replay_version})`;
    if (!robot.inputs || robot.inputs.length === 0) return 'none';
    return robot.inputs.map(([name, value]) => `${name} ${value}`).join(', ');
  }

  // A member's payload: its fields decoded with the run's message format
  // (decoded by syrof view, m[8]), else its bytes in hex.
  function payloadText(m) {
    if (m[8]) return m[8].map(([name, value]) => `${name} ${value}`).join(', ');
    if (!m[7]) return '–';
    return data.message && data.message !== 'none' ? `${m[7]} (bad length)` : m[7];
  }

  function inspector() {
    const body = $('inspector-body');
    if (selected < 0 || rounds === 0) {
      body.className = 'hint';
      body.textContent = 'Click a robot in the arena (or an event) to see its state and the LDMap it started its epoch with.';
      return null;
    }
    body.className = '';
    const robot = robots[selected];
    const f = frames[selected];
    const sample = sampleOf(pos);
    const s = f.s[sample];
    const err = Math.hypot(f.x[sample] - f.ex[sample], f.y[sample] - f.ey[sample]) / 1000;
    const pill = (text, c) => el('span', { className: 'pill', textContent: text, style: `background:${rgb(c)}` });
    const row = (name, value) => el('tr', {}, [el('td', { textContent: name }), el('td', {}, [value])]);
    const faulted = faultedFrom.has(robot.id) && faultedFrom.get(robot.id) <= pos;
    const facts = el('table', { className: 'facts' }, [
      row('robot', `${robot.id} (${KIND_NAMES[robot.kind] || 'kind ' + robot.kind}, body radius ${fmt(robot.radius, 3)} m)`),
      row('presence', faulted ? 'CRASHED (its app faulted)' : PRESENCE[presenceOf(s)]),
      row('status', joiningOf(s) ? 'joining' : 'member'),
      row('epoch', el('span', {}, [`${f.e[sample]} `, pill(MODES[modeOf(s)], modeOf(s) ? COLOURS.autonomous : COLOURS.cooperative), ` ${PHASES[phaseOf(s)]}`])),
      row('true pose', `(${fmt(f.x[sample] / 1000, 3)}, ${fmt(f.y[sample] / 1000, 3)}) m, ${fmt(f.h[sample] / 1000, 2)} rad`),
      row('estimate', `(${fmt(f.ex[sample] / 1000, 3)}, ${fmt(f.ey[sample] / 1000, 3)}) m, ${fmt(f.eh[sample] / 1000, 2)} rad`),
      row('error', `${fmt(err, 3)} m`),
      row('private inputs', privateInputs(robot)),
    ]);
    const children = [facts];
    // The LDMap of the robot's latest epoch start at or before now.
    const starts = startsOf[selected];
    let latest = null;
    for (const start of starts) { if (start.pos <= pos) latest = start; else break; }
    const report = { robot: robot.id, epoch: null, members: [], inputs: privateInputs(robot), payloads: [] };
    if (!latest) {
      children.push(el('h3', { textContent: 'LDMap' }),
                    el('div', { className: 'hint', textContent: data.replay_version >= 3 ? 'No epoch started yet.' : 'This replay (format version ' + data.replay_version + ') holds no maps.' }));
    } else {
      const [epoch, mode, members] = data.maps[latest.map];
      report.epoch = epoch;
      report.members = members.map((m) => m[0]);
      report.payloads = members.map(payloadText);
      const sharing = data.starts.filter((st) => st[2] === latest.map).length;
      children.push(el('h3', {}, [`LDMap it started epoch ${epoch} with `, pill(MODES[mode], mode ? COLOURS.autonomous : COLOURS.cooperative),
                                  ` (round ${roundIndex[latest.pos]}, ${members.length} members${sharing > 1 ? `, same map as ${sharing - 1} other robot start${sharing > 2 ? 's' : ''}` : ''})`,
                                  latest.active ? '' : ': ' + notLooking(latest)]));
      const head = el('tr', {}, ['id', 'phase', 'x', 'y', 'θ', 'vx', 'vy', 'payload'].map((t) => el('th', { textContent: t })));
      const rows = members.map((m) => {
        const tr = el('tr', {}, [m[0], PHASES[m[1]] || m[1], fmt(m[2] / 1000, 3), fmt(m[3] / 1000, 3), fmt(m[4] / 1000, 2),
                                 fmt(m[5] / 1000, 2), fmt(m[6] / 1000, 2), payloadText(m)].map((t) => el('td', { textContent: String(t) })));
        tr.dataset.member = m[0];
        if (m[0] === robot.id) tr.className = 'self';
        return tr;
      });
      children.push(el('div', { className: 'maptable' }, [el('table', { className: 'ldmap' }, [head, ...rows])]),
                    el('div', { className: 'hint', textContent: data.message ? `Message format: ${data.message}.` : 'No message format declared: payloads in hex.' }),
                    el('div', { className: 'hint', textContent: 'Each member\'s frozen snapshot as this robot\'s app received it: position (m), heading θ (rad), velocity (m/s), phase when last heard, and its payload: decoded with the run\'s message format when it declares one, else bytes in hex.' }));
    }
    body.replaceChildren(...children);
    return report;
  }

  // Why a start had no newRound: SSYNC left the robot out; under ASYNC its
  // cycle was under way.
  function notLooking(start) {
    if (start.lookEpoch === undefined) return 'left out of this epoch by the schedule (no newRound; it holds its place)';
    const cut = start.cut ? ', a move the scheduler cuts once it has covered the least distance' : '';
    return start.moves ? `no newRound (ASYNC): moving on its look of epoch ${start.lookEpoch}, a stale map${cut}`
                       : `no newRound (ASYNC): waiting to move on its look of epoch ${start.lookEpoch}${cut}`;
  }

  // ---- Events list and timeline --------------------------------------------------
  function describe(e) {
    if (e.partition >= 0) return `partition ${e.partition}`;
    if (e.kind === 'JOIN_WAIT') return `robot ${e.robot} waits to join: its start disc is not clear`;
    let text = e.robot >= 0 ? `robot ${e.robot}` : '';
    if (e.other >= 0) text += (e.kind === 'COLLISION' ? ' with ' : e.kind === 'SAFETY_INTERVENTION' ? ' kept from ' : ' → ') + `robot ${e.other}`;
    else if (e.kind === 'SAFETY_INTERVENTION') text += ' kept from a wall';
    if (e.robot >= 0) text += ` · epoch ${e.epoch} ${e.mode === 1 ? 'AUT' : 'COOP'}`;
    const out = e.kind === 'EPOCH_START' ? leftOut.get(e.pos + ':' + e.robot) : undefined;
    if (out && out.lookEpoch === undefined) text += ' · left out (inactive)';
    else if (out) text += out.moves ? ` · no look: moving on its look of epoch ${out.lookEpoch} (stale)` : ` · no look: waiting to move on its look of epoch ${out.lookEpoch}`;
    else if (e.kind === 'EPOCH_START' && data.activation && data.activation.model === 'async') text += ' · looks';
    return text;
  }
  let eventItems = [];
  function buildEvents(from) {
    const list = $('event-list');
    const fragment = document.createDocumentFragment();
    if (!from) eventItems = [];
    for (const e of events.slice(from || 0)) {
      const li = el('li', { className: 'ev k' + kinds.indexOf(e.kind) }, [
        el('span', { textContent: fmt(e.t, 2) + ' s' }),
        el('span', { className: 'kind', textContent: e.kind, style: `color:${KIND_COLOURS[e.kind] || '#333'}` }),
        el('span', { textContent: describe(e) }),
      ]);
      li.dataset.n = e.n;
      li.addEventListener('click', () => {
        const slot = slotOf.get(e.robot);
        if (slot !== undefined) selected = slot;
        seek(e.pos);
      });
      eventItems.push(li);
      fragment.append(li);
    }
    if (from) list.append(fragment); else list.replaceChildren(fragment);
    $('event-count').textContent = `(${events.length})`;
  }
  $('hide-starts').addEventListener('change', (ev) => $('event-list').classList.toggle('hide-starts', ev.target.checked));
  let nowItems = [];
  function markCurrentEvents() {
    for (const li of nowItems) li.classList.remove('now');
    nowItems = [];
    for (let n = lowerBound(pos); n < events.length && events[n].pos === pos; ++n) {
      eventItems[n].classList.add('now');
      nowItems.push(eventItems[n]);
    }
    if (playing || nowItems.length === 0) return;
    const item = nowItems.find((li) => li.offsetParent !== null);
    if (item) {
      const list = $('event-list');
      if (item.offsetTop < list.scrollTop || item.offsetTop > list.scrollTop + list.clientHeight - 20) list.scrollTop = item.offsetTop - list.offsetTop - 40;
    }
  }

  const timeline = $('timeline');
  const ROWS = [['EPOCH_START', 'MEMBER_REMOVED', 'MEMBER_JOINED', 'BECAME_JOINER'],
                ['CRASH', 'PAUSE', 'RESUME', 'JOIN', 'JOIN_WAIT', 'PARTITION_START', 'PARTITION_END', 'BEACON_LOST'],
                ['COLLISION', 'WALL_CONTACT', 'SAFETY_INTERVENTION', 'APP_FAULT', 'INVALID_COMMAND', 'PAYLOAD_REFUSED']];
  function drawTimeline() {
    const ctx = fitCanvas(timeline, 46);
    const w = timeline.clientWidth;
    ctx.clearRect(0, 0, w, 46);
    ctx.fillStyle = '#f4f5f7';
    ctx.fillRect(0, 0, w, 46);
    ctx.font = '9px system-ui, sans-serif';
    ctx.fillStyle = '#667085';
    ['sync', 'faults', 'contacts'].forEach((name, i) => ctx.fillText(name, 2, 12 + i * 14));
    const left = 44, width = w - left - 4;
    for (const e of events) {
      const row = ROWS.findIndex((r) => r.includes(e.kind));
      const x = left + (rounds > 1 ? e.pos / (rounds - 1) : 0) * width;
      ctx.fillStyle = KIND_COLOURS[e.kind] || '#333';
      ctx.fillRect(Math.round(x), 3 + Math.max(0, row) * 14, e.kind === 'EPOCH_START' ? 1 : 2, 12);
    }
    const cx = left + (rounds > 1 ? pos / (rounds - 1) : 0) * width;
    ctx.fillStyle = '#111';
    ctx.fillRect(Math.round(cx) - 1, 0, 2, 46);
    timeline.onclick = (ev) => {
      const x = ev.offsetX - left;
      seek(Math.round(Math.max(0, Math.min(1, x / width)) * (rounds - 1)));
    };
  }

  // ---- Plots ------------------------------------------------------------------------
  function fitCanvas(canvas, height) {
    const ratio = window.devicePixelRatio || 1;
    const w = canvas.clientWidth || 300;
    if (canvas.width !== Math.round(w * ratio) || canvas.height !== Math.round(height * ratio)) {
      canvas.width = Math.round(w * ratio);
      canvas.height = Math.round(height * ratio);
      canvas.style.height = height + 'px';
    }
    const ctx = canvas.getContext('2d');
    ctx.setTransform(ratio, 0, 0, ratio, 0, 0);
    return ctx;
  }
  const PAD = { l: 40, r: 8, t: 6, b: 18 };

  function axes(ctx, w, h, yMax, yLabel, xLabels) {
    ctx.strokeStyle = '#c5cad3';
    ctx.lineWidth = 1;
    ctx.beginPath();
    ctx.moveTo(PAD.l, PAD.t); ctx.lineTo(PAD.l, h - PAD.b); ctx.lineTo(w - PAD.r, h - PAD.b);
    ctx.stroke();
    ctx.fillStyle = '#667085';
    ctx.font = '10px system-ui, sans-serif';
    ctx.textAlign = 'right';
    ctx.fillText(yLabel(yMax), PAD.l - 4, PAD.t + 8);
    ctx.fillText(yLabel(0), PAD.l - 4, h - PAD.b);
    ctx.textAlign = 'left';
    ctx.fillText(xLabels[0], PAD.l, h - 4);
    ctx.textAlign = 'right';
    ctx.fillText(xLabels[1], w - PAD.r, h - 4);
    ctx.textAlign = 'left';
  }

  // Per-sample series and per-epoch figures, computed once (live: at each
  // update).
  let errorMean, errorMax, epochs;
  function deriveSeries() {
  errorMean = new Float64Array(samples); errorMax = new Float64Array(samples);
  for (let i = 0; i < samples; ++i) {
    let sum = 0, n = 0, max = 0;
    for (let slot = 0; slot < robots.length; ++slot) {
      const f = frames[slot];
      if (presenceOf(f.s[i]) !== 1) continue;
      const e = Math.hypot(f.x[i] - f.ex[i], f.y[i] - f.ey[i]) / 1000;
      sum += e; ++n; if (e > max) max = e;
    }
    errorMean[i] = n ? sum / n : NaN;
    errorMax[i] = n ? max : NaN;
  }
  // Epochs in the order they first started; skew and COOPERATIVE share.
  epochs = [];
  {
    const byEpoch = new Map();
    for (const e of events) {
      if (e.kind !== 'EPOCH_START') continue;
      let entry = byEpoch.get(e.epoch);
      // An epoch number comes back after 65536 epochs (or when a group runs
      // far ahead): a start long after the last one opens a new entry.
      if (entry && e.pos - entry.last > 200) entry = undefined;
      if (!entry) { entry = { epoch: e.epoch, first: e.pos, last: e.pos, starts: 0, coop: 0 }; byEpoch.set(e.epoch, entry); epochs.push(entry); }
      entry.last = e.pos; entry.starts += 1; if (e.mode === 0) entry.coop += 1;
    }
  }
  }
  deriveSeries();

  function drawModes() {
    const canvas = $('plot-modes');
    const rowH = Math.max(2, Math.min(12, Math.floor(180 / Math.max(1, robots.length))));
    const h = PAD.t + rowH * robots.length + PAD.b;
    const ctx = fitCanvas(canvas, h);
    const w = canvas.clientWidth;
    ctx.clearRect(0, 0, w, h);
    const width = w - PAD.l - PAD.r;
    if (samples > 0 && width > 0) {
      for (let slot = 0; slot < robots.length; ++slot) {
        const s = frames[slot].s;
        let runStart = 0, runColour = null;
        const flush = (end) => {
          if (runColour) { ctx.fillStyle = rgb(runColour); ctx.fillRect(PAD.l + runStart, PAD.t + slot * rowH, end - runStart, Math.max(1, rowH - 1)); }
        };
        for (let x = 0; x < width; ++x) {
          const i = Math.min(samples - 1, Math.floor(x / width * samples));
          const colour = presenceOf(s[i]) === 0 ? null : robotColour(s[i], slot, i * stride);
          if (colour !== runColour) { flush(x); runStart = x; runColour = colour; }
        }
        flush(width);
      }
    }
    ctx.fillStyle = '#667085';
    ctx.font = '10px system-ui, sans-serif';
    ctx.textAlign = 'right';
    if (rowH >= 9) robots.forEach((r, slot) => ctx.fillText('robot ' + r.id, PAD.l - 4, PAD.t + slot * rowH + rowH - 2));
    else { ctx.fillText('robot ' + robots[0].id, PAD.l - 4, PAD.t + 8); ctx.fillText(String(robots[robots.length - 1].id), PAD.l - 4, h - PAD.b); }
    ctx.textAlign = 'left';
    ctx.fillText('0 s', PAD.l, h - 4);
    ctx.textAlign = 'right';
    ctx.fillText(fmt(duration, 1) + ' s', w - PAD.r, h - 4);
    ctx.textAlign = 'left';
    cursor(ctx, w, h);
    canvas.onclick = (ev) => seekX(ev.offsetX, w);
  }

  function cursor(ctx, w, h) {
    const x = PAD.l + (rounds > 1 ? pos / (rounds - 1) : 0) * (w - PAD.l - PAD.r);
    ctx.fillStyle = '#111';
    ctx.fillRect(Math.round(x) - 1, PAD.t, 2, h - PAD.t - PAD.b);
  }
  function seekX(x, w) {
    const f = (x - PAD.l) / (w - PAD.l - PAD.r);
    seek(Math.round(Math.max(0, Math.min(1, f)) * (rounds - 1)));
  }

  function drawError() {
    const canvas = $('plot-error');
    const h = 150;
    const ctx = fitCanvas(canvas, h);
    const w = canvas.clientWidth;
    ctx.clearRect(0, 0, w, h);
    let yMax = 0;
    for (const v of errorMax) if (Number.isFinite(v) && v > yMax) yMax = v;
    yMax = yMax > 0 ? yMax * 1.1 : 0.1;
    axes(ctx, w, h, yMax, (v) => fmt(v, 2), ['0 s', fmt(duration, 1) + ' s']);
    const width = w - PAD.l - PAD.r, height = h - PAD.t - PAD.b;
    const line = (series, colour) => {
      ctx.strokeStyle = colour; ctx.lineWidth = 1.5; ctx.beginPath();
      let started = false;
      for (let i = 0; i < samples; ++i) {
        if (!Number.isFinite(series[i])) { started = false; continue; }
        const x = PAD.l + (samples > 1 ? i / (samples - 1) : 0) * width;
        const y = PAD.t + height - series[i] / yMax * height;
        if (started) ctx.lineTo(x, y); else ctx.moveTo(x, y);
        started = true;
      }
      ctx.stroke();
    };
    line(errorMax, '#d0452f');
    line(errorMean, '#2f7fd0');
    cursor(ctx, w, h);
    canvas.onclick = (ev) => seekX(ev.offsetX, w);
  }

  function drawEpochBars(id, value, yMax, yLabel, colourOf) {
    const canvas = $(id);
    const h = 150;
    const ctx = fitCanvas(canvas, h);
    const w = canvas.clientWidth;
    ctx.clearRect(0, 0, w, h);
    const first = epochs.length ? epochs[0].epoch : 0, last = epochs.length ? epochs[epochs.length - 1].epoch : 0;
    axes(ctx, w, h, yMax, yLabel, ['epoch ' + first, 'epoch ' + last]);
    const width = w - PAD.l - PAD.r, height = h - PAD.t - PAD.b;
    const bar = width / Math.max(1, epochs.length);
    let current = -1;
    epochs.forEach((entry, i) => {
      if (entry.first <= pos) current = i;
      const v = value(entry);
      const bh = Math.max(v > 0 ? 1 : 0, v / yMax * height);
      ctx.fillStyle = colourOf(entry);
      ctx.fillRect(PAD.l + i * bar + (bar > 3 ? 0.5 : 0), PAD.t + height - bh, Math.max(1, bar - (bar > 3 ? 1 : 0)), bh);
    });
    if (current >= 0) {
      ctx.strokeStyle = '#111'; ctx.lineWidth = 1.5;
      ctx.strokeRect(PAD.l + current * bar, PAD.t, Math.max(2, bar), height);
    }
    canvas.onclick = (ev) => {
      const i = Math.floor((ev.offsetX - PAD.l) / bar);
      if (i >= 0 && i < epochs.length) seek(epochs[i].first);
    };
  }
  function drawSkew() {
    let max = 1;
    for (const e of epochs) max = Math.max(max, e.last - e.first);
    drawEpochBars('plot-skew', (e) => e.last - e.first, max, (v) => Math.round(v) + ' r',
                  (e) => (e.last - e.first > 2 ? '#d0452f' : '#7d8699'));
    if (epochs.length && epochs.every((e) => e.last === e.first)) {
      const canvas = $('plot-skew');
      const ctx = canvas.getContext('2d');
      ctx.fillStyle = '#2e9d5b';
      ctx.font = '12px system-ui, sans-serif';
      ctx.fillText(`Skew 0 in all ${epochs.length} epochs: every robot started each epoch in the same round.`, PAD.l + 10, 40);
    }
  }
  function drawCoop() {
    drawEpochBars('plot-coop', (e) => e.coop / e.starts, 1, (v) => Math.round(v * 100) + '%',
                  (e) => (e.coop === e.starts ? rgb(COLOURS.cooperative) : e.coop === 0 ? rgb(COLOURS.autonomous) : '#b38bd9'));
  }

  // ---- Putting it together ----------------------------------------------------------
  function clock() {
    const sample = sampleOf(pos);
    const epochsNow = new Set();
    for (let slot = 0; slot < robots.length; ++slot) if (presenceOf(frames[slot].s[sample]) === 1) epochsNow.add(frames[slot].e[sample]);
    epochsNow.delete(0);  // a robot that has not started an epoch yet
    const epochText = epochsNow.size === 0 ? 'none yet (starting)' : [...epochsNow].sort((a, b) => a - b).join(', ');
    $('clock').innerHTML = '';
    $('clock').append(el('b', { textContent: `t = ${fmt(timeOf(pos), 2)} s` }),
                      ` · round ${rounds ? roundIndex[pos] : '-'} · epoch ${epochText}`);
  }

  function render() {
    const arenaReport = drawArena();
    const inspected = inspector();
    drawTimeline();
    drawModes(); drawError(); drawSkew(); drawCoop();
    clock();
    markCurrentEvents();
    $('scrubber').value = String(pos);
    $('play').innerHTML = playing ? '&#10074;&#10074;' : '&#9654;';
    const rect = arena.getBoundingClientRect();
    lastReport = {
      round: rounds ? roundIndex[pos] : null, position: pos, stride,
      robots_drawn: arenaReport.robots_drawn, marks: arenaReport.marks, left_out: arenaReport.left_out || [],
      events_listed: eventItems.length, inspector: inspected,
      verdict: verdictShown, targets: arenaReport.targets, labels: arenaReport.labels,

      arena: { left: rect.left + window.scrollX, top: rect.top + window.scrollY, ox: view.ox, oy: view.oy, scale: view.scale },
      colours: COLOURS,
    };
    return lastReport;
  }

  function seek(p) {
    pos = Math.max(0, Math.min(rounds - 1, Math.round(p)));
    if (live) live.follow = pos >= rounds - 1;  // back to the newest: follow again
    render();
  }

  // Playback in simulated time: the clock runs at speed x wall time and the
  // page shows the last round at or before it.
  let lastFrame = 0;
  let playClock = 0;  // microseconds of simulated time
  function tick(now) {
    if (!playing) return;
    const dt = lastFrame ? Math.min(0.25, (now - lastFrame) / 1000) : 0;
    lastFrame = now;
    playClock += dt * speed * 1e6;
    let p = pos;
    while (p + 1 < rounds && roundTime[p + 1] <= playClock) ++p;
    if (p >= rounds - 1) { pos = rounds - 1; playing = false; render(); return; }
    if (p !== pos) { pos = p; render(); }
    requestAnimationFrame(tick);
  }
  function setPlaying(on) {
    playing = on && rounds > 1;
    if (playing && pos >= rounds - 1) pos = 0;
    lastFrame = 0;
    playClock = rounds ? roundTime[pos] : 0;
    render();
    if (playing) requestAnimationFrame(tick);
  }

  function step(n) { seek(pos + n * stride); }
  function jumpEvent(direction) {
    // Next or previous event that is not an EPOCH_START (those are every epoch).
    if (direction > 0) {
      for (let n = lowerBound(pos + 1); n < events.length; ++n) if (events[n].kind !== 'EPOCH_START') return seek(events[n].pos);
    } else {
      for (let n = lowerBound(pos) - 1; n >= 0; --n) if (events[n].kind !== 'EPOCH_START') return seek(events[n].pos);
    }
  }

  // ---- Wiring ---------------------------------------------------------------------------
  $('scrubber').max = String(Math.max(0, rounds - 1));
  $('scrubber').step = String(stride);
  $('scrubber').addEventListener('input', (ev) => seek(Number(ev.target.value)));
  $('play').addEventListener('click', () => setPlaying(!playing));
  $('back').addEventListener('click', () => step(-1));
  $('forward').addEventListener('click', () => step(1));
  $('speed').addEventListener('change', (ev) => { speed = Number(ev.target.value); });
  arena.addEventListener('click', (ev) => {
    const rect = arena.getBoundingClientRect();
    const x = ev.clientX - rect.left, y = ev.clientY - rect.top;
    const sample = sampleOf(pos);
    let best = -1, bestD = Infinity;
    for (let slot = 0; slot < robots.length; ++slot) {
      const f = frames[slot];
      if (presenceOf(f.s[sample]) === 0) continue;
      const d = Math.hypot(sx(f.x[sample] / 1000) - x, sy(f.y[sample] / 1000) - y);
      const r = Math.max(8, robots[slot].radius * view.scale + 4);
      if (d < r && d < bestD) { best = slot; bestD = d; }
    }
    selected = best;
    render();
  });
  document.addEventListener('keydown', (ev) => {
    if (ev.target.tagName === 'INPUT' && ev.target.type !== 'range' && ev.target.type !== 'checkbox') return;
    const speeds = [...$('speed').options].map((o) => Number(o.value));
    switch (ev.key) {
      case ' ': setPlaying(!playing); break;
      case 'ArrowRight': step(ev.shiftKey ? Math.round(1e9 / data.round_ns / stride) : 1); break;
      case 'ArrowLeft': step(ev.shiftKey ? -Math.round(1e9 / data.round_ns / stride) : -1); break;
      case 'Home': seek(0); break;
      case 'End': seek(rounds - 1); break;
      case 'n': case 'N': jumpEvent(1); break;
      case 'p': case 'P': jumpEvent(-1); break;
      case ']': case '[': {
        const i = speeds.indexOf(speed) + (ev.key === ']' ? 1 : -1);
        if (i >= 0 && i < speeds.length) { speed = speeds[i]; $('speed').value = String(speed); }
        break;
      }
      case 'Escape': selected = -1; render(); break;
      default: return;
    }
    ev.preventDefault();
  });
  window.addEventListener('resize', () => { layoutArena(); render(); });

  // ---- Start ------------------------------------------------------------------------------
  timings.decode_ms = Math.round(performance.now() - scriptStart);
  legend();
  buildEvents();
  timings.events_ms = Math.round(performance.now() - scriptStart);
  layoutArena();
  const params = new URLSearchParams(location.hash.replace(/^#/, ''));
  if (params.has('round') && rounds) {
    const wanted = Number(params.get('round'));
    let p = 0;
    while (p + 1 < rounds && roundIndex[p + 1] <= wanted) ++p;
    pos = p;
  }
  if (params.has('robot')) {
    const slot = slotOf.get(Number(params.get('robot')));
    if (slot !== undefined) selected = slot;
  }
  const report = render();
  timings.render_ms = Math.round(performance.now() - scriptStart);
  if (verdictShown) {
    const box = $('verdict').getBoundingClientRect();
    report.verdict.top = box.top + window.scrollY;
    report.verdict.bottom = box.bottom + window.scrollY;
  }
  // Event kinds whose name does not fit its column (one item of each kind).
  const kindItems = new Map();
  for (const li of eventItems) if (!kindItems.has(li.children[1].textContent)) kindItems.set(li.children[1].textContent, li.children[1]);
  report.events_overflowing = [...kindItems].filter(([, span]) => span.scrollWidth > span.clientWidth).map(([kind]) => kind);
  report.timings = timings;
  if (live) {
    live.follow = true;
    live.update = scheduleLive;
    live.updateNow = () => { clearTimeout(live.timer); live.timer = null; applyLive(); };
    scheduleLive();
  }
  finish(report);

  // ---- Live updates ------------------------------------------------------------------------
  // Rounds are appended as they arrive and drawn at most every 100 ms.
  function scheduleLive() {
    if (live.timer) return;
    live.timer = setTimeout(() => { live.timer = null; applyLive(); }, Math.max(0, 100 - (performance.now() - live.updated)));
  }
  function appendRound(r) {
    const at = data.rounds.index.length;
    data.rounds.index.push(r.i);
    data.rounds.time_us.push(r.t);
    r.f.forEach((f, slot) => {
      const c = data.frames[slot];
      c.s.push(f[0]); c.e.push(f[1]); c.x.push(f[2]); c.y.push(f[3]); c.h.push(f[4]); c.ex.push(f[5]); c.ey.push(f[6]); c.eh.push(f[7]);
    });
    for (const e of r.ev) { e[0] = at; data.events.push(e); }
    const base = data.maps.length;
    for (const m of r.m) data.maps.push(m);
    for (const [robot, k] of r.st) data.starts.push([at, robot, base + k]);
    live.lastWallUs = r.w;
  }
  // Keeps the page's memory bounded: the oldest rounds go first.
  function trimLive() {
    const drop = data.rounds.index.length - LIVE_MAX_ROUNDS;
    if (drop <= 0) return false;
    data.rounds.index.splice(0, drop);
    data.rounds.time_us.splice(0, drop);
    for (const c of data.frames) for (const key of Object.keys(c)) c[key].splice(0, drop);
    data.events = data.events.filter((e) => e[0] >= drop).map((e) => { e[0] -= drop; return e; });
    data.starts = data.starts.filter((st) => st[0] >= drop).map((st) => [st[0] - drop, st[1], st[2]]);
    pos = Math.max(0, pos - drop);
    return true;
  }
  function applyLive() {
    live.updated = performance.now();
    const before = events.length;
    let arrived = live.pending;
    live.pending = [];
    // The browser test's stop after exactly N rounds (live-until=rounds:N).
    const untilRounds = /(?:^|&)live-until=rounds:(\d+)/.exec(location.hash.replace(/^#/, ''));
    if (untilRounds) arrived = arrived.slice(0, Math.max(0, Number(untilRounds[1]) - data.rounds.index.length));
    for (const r of arrived) appendRound(r);
    live.drawnW = live.lastWallUs;
    const trimmed = trimLive();
    deriveRounds();
    deriveSeries();
    runFacts();
    if (trimmed) buildEvents(); else if (events.length > before) buildEvents(before);
    $('scrubber').max = String(Math.max(0, rounds - 1));
    if (live.follow && !playing) pos = Math.max(0, rounds - 1);
    const newest = rounds ? roundIndex[rounds - 1] : '-';
    if (live.ended) {
      const banner = $('banner');
      banner.hidden = false;
      banner.className = 'ended';
      const text = el('div', { textContent: live.ended.complete ? 'The run ended. ' : 'The run stopped before its end. ' });
      if (live.ended.replay) text.append(el('a', { href: live.ended.replay, textContent: 'Open the replay', id: 'replay-link' }), ' (the whole run, from its replay file).');
      else text.append('It wrote no replay page.');
      banner.replaceChildren(el('h2', { textContent: 'Run ended' }), text);
    } else {
      showBanner('live', '● Live', (live.follow ? 'Following the run' : 'Paused on an earlier round (press End to follow the run again)') +
                 ` · newest round ${newest}` + (live.skipped ? ` · ${live.skipped} rounds skipped (this browser fell behind)` : ''));
      $('banner').className = 'live';
    }
    // When each robot was first drawn crashed (what the browser test checks:
    // a crash shows within 1 s).
    if (rounds) {
      for (let slot = 0; slot < robots.length; ++slot) {
        const id = robots[slot].id;
        if (presenceOf(frames[slot].s[rounds - 1]) === 3 && !(id in live.crashShown)) {
          // The recording's wall time of the newest round drawn: the crash
          // was recorded at or before it.
          live.crashShown[id] = live.lastWallUs;
        }
      }
    }
    const report = render();
    const until = new URLSearchParams(location.hash.replace(/^#/, '')).get('live-until');
    let stop = false;
    if (until && until.startsWith('rounds:')) stop = rounds >= Number(until.slice(7));
    if (until && until.startsWith('crash:')) stop = String(Number(until.slice(6))) in live.crashShown;
    if (stop && !live.ended) { live.source.close(); live.stoppedByFragment = true; }
    report.live = { rounds, newest_round: rounds ? roundIndex[rounds - 1] : null, newest_time_us: rounds ? roundTime[rounds - 1] : null,
                    following: live.follow, skipped: live.skipped, ended: live.ended, crash_shown_w_us: live.crashShown,
                    stopped: !!live.stoppedByFragment, drawn_wall_us: Date.now() * 1000,
                    positions: robots.map((r, slot) => (rounds ? [frames[slot].x[rounds - 1], frames[slot].y[rounds - 1], presenceOf(frames[slot].s[rounds - 1])] : null)) };
    finish(report);
    if (live.pending.length && !live.stoppedByFragment) scheduleLive();
  }
  }  // start()
})();
