// lgi/apps/viewer/viewer.js — the page of `lgi view` (apps/view.hpp): a run's frames animated with three.js r111.
// The data: #lgi-meta (JSON) and #lgi-data (base64: t as float64, then q = (w, x, y, z), Ω, and each curve's
// low and high since the previous frame, the rotors' angles, as float32, frame-major). window.lgiView is the page's interface for
// tests and scripts: state(), play(), pause(), seek(frame), setSpeed(factor).
(function () {
  'use strict';
  const meta = JSON.parse(document.getElementById('lgi-meta').textContent);
  const F = meta.frames, C = meta.curves.length;
  const message = (text) => {
    const m = document.getElementById('message');
    m.textContent = text;
    m.style.display = 'flex';
  };

  // The frames.
  const raw = atob(document.getElementById('lgi-data').textContent.trim());
  const buffer = new ArrayBuffer(raw.length);
  const bytes = new Uint8Array(buffer);
  for (let i = 0; i < raw.length; ++i) bytes[i] = raw.charCodeAt(i);
  let offset = 0;
  const take = (Type, count) => {
    const a = new Type(buffer, offset, count);
    offset += count * Type.BYTES_PER_ELEMENT;
    return a;
  };
  const t = take(Float64Array, F);
  const q = take(Float32Array, 4 * F);
  const omega = meta.has_omega ? take(Float32Array, 3 * F) : null;
  const lo = take(Float32Array, C * F);
  const hi = take(Float32Array, C * F);
  const rotorCount = meta.body.known ? meta.body.rotors.length : 0;
  const rotorAngle = meta.rotor_angles ? take(Float32Array, rotorCount * F) : null;
  if (offset !== buffer.byteLength) throw new Error('lgi view: the page data has ' + buffer.byteLength + ' bytes, expected ' + offset);
  const t0 = t[0], tEnd = t[F - 1], span = tEnd - t0;

  // R(q) e_i, column i of the rotation of the unit quaternion of frame j (Hamilton, x_lab = R x_body).
  const column = (j, i, out) => {
    const w = q[4 * j], x = q[4 * j + 1], y = q[4 * j + 2], z = q[4 * j + 3];
    if (i === 0) out.set(1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y));
    else if (i === 1) out.set(2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x));
    else out.set(2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y));
    return out;
  };

  const format = (x) => {
    if (x === 0) return '0';
    const a = Math.abs(x);
    if (a >= 1e-3 && a < 1e6) return String(Number(x.toPrecision(6)));
    return x.toExponential(3);
  };

  document.title = meta.title;
  document.getElementById('title').textContent = meta.title;
  const body = meta.body;
  const every = F < meta.rows ? Math.round((meta.rows - 1) / (F - 1)) : 1;
  document.getElementById('info').textContent =
      (body.known ? body.problem : 'body not known (lgi view --scene SCENE draws its inertia ellipsoid)') + ' · ' +
      meta.rows.toLocaleString('en') + ' rows, t = ' + format(t0) + ' … ' + format(tEnd) + ' · ' +
      (F < meta.rows ? 'shown: ' + F.toLocaleString('en') + ' frames (about one row in ' + every + '); the curves ' +
                           'show each value\'s range over all rows'
                     : 'shown: every row');

  // The scene.
  const canvas = document.getElementById('scene');
  // Antialiasing, except on a software WebGL (SwiftShader, llvmpipe): docs/viewer.md.
  const softwareGL = (() => {
    try {
      const g = document.createElement('canvas').getContext('webgl');
      if (!g) return false;
      const info = g.getExtension('WEBGL_debug_renderer_info');
      const name = String(g.getParameter(info ? info.UNMASKED_RENDERER_WEBGL : g.RENDERER));
      const lose = g.getExtension('WEBGL_lose_context');
      if (lose) lose.loseContext();
      return /swiftshader|llvmpipe|softpipe|software/i.test(name);
    } catch (e) {
      return false;
    }
  })();
  let renderer;
  try {
    renderer = new THREE.WebGLRenderer({canvas: canvas, antialias: !softwareGL});
  } catch (e) {
    message('This browser cannot draw WebGL (' + e.message + '): the 3D view needs it. The curves are on the right.');
  }
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0x14171c);
  const camera = new THREE.PerspectiveCamera(38, 1, 0.01, 100);
  camera.up.set(0, 0, 1);
  camera.position.set(3.4, -4.2, 2.5);
  let controls = null;
  if (renderer) {
    controls = new THREE.OrbitControls(camera, canvas);
    controls.target.set(0, 0, 0.1);
    controls.update();
  }
  scene.add(new THREE.AmbientLight(0xffffff, 0.5));
  const sun = new THREE.DirectionalLight(0xffffff, 0.7);
  sun.position.set(3, -2, 5);
  scene.add(sun);
  scene.add(new THREE.AxesHelper(1.5));
  const sphere = new THREE.Mesh(new THREE.SphereBufferGeometry(1, 36, 18),
                                new THREE.MeshBasicMaterial({color: 0x7a8494, wireframe: true, transparent: true, opacity: 0.10}));
  sphere.rotation.x = Math.PI / 2;
  scene.add(sphere);

  const line = (points, color, opacity) => {
    const g = new THREE.BufferGeometry();
    g.addAttribute('position', new THREE.BufferAttribute(new Float32Array(points), 3));
    return new THREE.Line(g, new THREE.LineBasicMaterial({color: color, transparent: opacity < 1, opacity: opacity}));
  };

  // The body: its frame follows the run's attitude.
  const frame = new THREE.Group();
  scene.add(frame);
  const bodyColors = (geometry, a, b) => {  // eight sectors about the principal 3-axis, to show spin about it
    const p = geometry.attributes.position, colors = new Float32Array(p.count * 3);
    const ca = new THREE.Color(a), cb = new THREE.Color(b);
    for (let i = 0; i < p.count; ++i) {
      const sector = Math.floor((Math.atan2(p.getY(i), p.getX(i)) + Math.PI) / (Math.PI / 4)) % 8;
      const c = (sector % 2 === 0) !== (p.getZ(i) > 0) ? ca : cb;
      colors.set([c.r, c.g, c.b], 3 * i);
    }
    geometry.addAttribute('color', new THREE.BufferAttribute(colors, 3));
  };
  const rotors = [];
  if (body.known) {
    const s = body.semi_axes, size = body.gravity ? 0.45 : 0.75;
    const geometry = new THREE.SphereBufferGeometry(1, 48, 32);
    geometry.rotateX(Math.PI / 2);
    bodyColors(geometry, 0x4f8fd6, 0x2f5f9a);
    const mesh = new THREE.Mesh(geometry, new THREE.MeshPhongMaterial({vertexColors: THREE.VertexColors, shininess: 40}));
    mesh.scale.set(size * s[0], size * s[1], size * s[2]);
    const principal = new THREE.Group();
    const P = body.principal;
    principal.quaternion.setFromRotationMatrix(new THREE.Matrix4().set(
        P[0][0], P[0][1], P[0][2], 0, P[1][0], P[1][1], P[1][2], 0, P[2][0], P[2][1], P[2][2], 0, 0, 0, 0, 1));
    principal.add(mesh);
    if (body.gravity) {  // the centre of mass along z0, the fixed point at the ellipsoid's surface
      const z = body.z0;
      let extent = 0;
      for (let i = 0; i < 3; ++i) {
        const u = P[0][i] * z[0] + P[1][i] * z[1] + P[2][i] * z[2];
        extent += (size * s[i] * u) * (size * s[i] * u);
      }
      extent = Math.sqrt(extent);
      principal.position.set(extent * z[0], extent * z[1], extent * z[2]);
      frame.add(line([0, 0, 0, extent * z[0], extent * z[1], extent * z[2]], 0xd8dde6, 1));
    }
    frame.add(principal);
    // A gyrostat's rotors: discs on their axes just outside the ellipsoid, a spoke on each to show its turning.
    for (const a of body.rotors) {
      let extent = 0;
      for (let i = 0; i < 3; ++i) {
        const u = P[0][i] * a[0] + P[1][i] * a[1] + P[2][i] * a[2];
        extent += (size * s[i] * u) * (size * s[i] * u);
      }
      extent = Math.sqrt(extent) + 0.1;
      const holder = new THREE.Group();
      holder.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), new THREE.Vector3().fromArray(a));
      holder.position.copy(principal.position).add(new THREE.Vector3().fromArray(a).multiplyScalar(extent));
      const wheel = new THREE.Group();
      wheel.add(new THREE.Mesh(new THREE.CylinderBufferGeometry(0.2, 0.2, 0.05, 32),
                               new THREE.MeshPhongMaterial({color: 0xc8a85a, shininess: 60})));
      const spoke = new THREE.Mesh(new THREE.BoxBufferGeometry(0.36, 0.06, 0.05), new THREE.MeshBasicMaterial({color: 0x3a2a10}));
      wheel.add(spoke);
      holder.add(wheel);
      frame.add(holder);
      rotors.push(wheel);
    }
  } else {
    const geometry = new THREE.BoxBufferGeometry(1.1, 0.8, 0.5);
    frame.add(new THREE.Mesh(geometry, new THREE.MeshPhongMaterial({color: 0x4f8fd6, transparent: true, opacity: 0.9})));
  }
  const bodyAxisColors = [0xff9a9a, 0x9aff9a, 0x9ac8ff];
  for (let i = 0; i < 3; ++i) {
    const e = [0, 0, 0];
    e[i] = 1;
    frame.add(line([0, 0, 0].concat(e), bodyAxisColors[i], 1));
  }

  // The trace of R e_axis on the unit sphere.
  const axis = meta.axis - 1;
  const tracePoints = new Float32Array(3 * F);
  const v = new THREE.Vector3();
  for (let j = 0; j < F; ++j) {
    column(j, axis, v);
    tracePoints.set([v.x, v.y, v.z], 3 * j);
  }
  const traceGeometry = new THREE.BufferGeometry();
  traceGeometry.addAttribute('position', new THREE.BufferAttribute(tracePoints, 3));
  scene.add(new THREE.Line(traceGeometry, new THREE.LineBasicMaterial({color: 0xf0a030})));
  const tip = new THREE.Mesh(new THREE.SphereBufferGeometry(0.03, 12, 8), new THREE.MeshBasicMaterial({color: 0xf0a030}));
  scene.add(tip);

  // Gravity, Ω and the angular momentum.
  const legend = [['#f0a030', 'trace of body axis e' + meta.axis], ['#ff5050', 'lab x y z (body axes lighter)']];
  if (body.known && body.gravity) {
    const k = new THREE.Vector3().fromArray(body.k);
    const side = new THREE.Vector3().crossVectors(k, Math.abs(k.x) < 0.9 ? new THREE.Vector3(1, 0, 0) : new THREE.Vector3(0, 1, 0)).normalize();
    const origin = side.multiplyScalar(1.6).add(k.clone().multiplyScalar(0.9));
    scene.add(new THREE.ArrowHelper(k.clone().negate(), origin, 0.8, 0x9aa3b0, 0.15, 0.07));
    legend.push(['#9aa3b0', 'gravity −k']);
  }
  const arrow = (color) => {
    const a = new THREE.ArrowHelper(new THREE.Vector3(0, 0, 1), new THREE.Vector3(0, 0, 0), 1, color, 0.12, 0.06);
    scene.add(a);
    return a;
  };
  const J = body.known ? body.J : null;
  const omegaArrow = omega ? arrow(0xe050e0) : null;
  const momentumArrow = omega && J ? arrow(0x40d0d0) : null;
  const lab = (j, vector, out) => {  // R(q_j) vector
    const c0 = column(j, 0, new THREE.Vector3()), c1 = column(j, 1, new THREE.Vector3()), c2 = column(j, 2, new THREE.Vector3());
    return out.copy(c0.multiplyScalar(vector[0])).add(c1.multiplyScalar(vector[1])).add(c2.multiplyScalar(vector[2]));
  };
  const bodyOmega = (j) => [omega[3 * j], omega[3 * j + 1], omega[3 * j + 2]];
  const bodyMomentum = (j) => {
    const w = bodyOmega(j);
    return [0, 1, 2].map((r) => J[r][0] * w[0] + J[r][1] * w[1] + J[r][2] * w[2]);
  };
  const norm = (a) => Math.hypot(a[0], a[1], a[2]);
  let omegaMax = 0, momentumMax = 0;
  for (let j = 0; omega && j < F; ++j) {
    omegaMax = Math.max(omegaMax, norm(bodyOmega(j)));
    if (J) momentumMax = Math.max(momentumMax, norm(bodyMomentum(j)));
  }
  if (omegaArrow) legend.push(['#e050e0', 'angular velocity RΩ (scaled)']);
  if (momentumArrow) legend.push(['#40d0d0', 'angular momentum RJΩ (scaled)']);
  const legendBox = document.getElementById('legend');
  for (const [color, text] of legend) {
    const row = document.createElement('div');
    const sw = document.createElement('span');
    sw.className = 'sw';
    sw.style.background = color;
    row.appendChild(sw);
    row.appendChild(document.createTextNode(text));
    legendBox.appendChild(row);
  }
  const setArrow = (a, vector, largest) => {
    const length = norm(vector);
    a.visible = length > 0 && largest > 0;
    if (!a.visible) return;
    a.setDirection(new THREE.Vector3(vector[0], vector[1], vector[2]).divideScalar(length));
    a.setLength(1.4 * length / largest, 0.12, 0.06);
  };

  // The curves.
  const side = document.getElementById('side');
  const plots = [];
  const addPlot = (title, series) => {
    const h = document.createElement('h2');
    h.textContent = title;
    const range = document.createElement('div');
    range.className = 'range';
    const c = document.createElement('canvas');
    side.appendChild(h);
    side.appendChild(range);
    side.appendChild(c);
    let low = Infinity, high = -Infinity;
    for (const s of series)
      for (let j = 0; j < F; ++j) {
        low = Math.min(low, s.lo(j));
        high = Math.max(high, s.hi(j));
      }
    range.textContent = 'from ' + format(low) + ' to ' + format(high);
    if (!(high > low)) {
      low -= 1;
      high += 1;
    }
    const pad = 0.06 * (high - low);
    plots.push({canvas: c, series: series, low: low - pad, high: high + pad, base: null});
    c.addEventListener('pointerdown', (e) => seekTime(e, c));
    c.addEventListener('pointermove', (e) => { if (e.buttons & 1) seekTime(e, c); });
  };
  for (let c = 0; c < C; ++c) {
    const name = meta.curves[c].name;
    addPlot(name + ' − its value at t = ' + format(t0) + ' (' + format(meta.curves[c].v0) + ')',
            [{lo: (j) => lo[j * C + c], hi: (j) => hi[j * C + c], color: '#f0c060'}]);
  }
  if (omega) {
    const colors = ['#ff7070', '#70e070', '#70a8ff'];
    addPlot('Ω1, Ω2, Ω3 (body frame; red, green, blue)',
            [0, 1, 2].map((i) => ({lo: (j) => omega[3 * j + i], hi: (j) => omega[3 * j + i], color: colors[i]})));
  }
  const note = document.createElement('div');
  note.className = 'note';
  note.textContent = 'Drag to turn the view, scroll to zoom; click a curve to go to that time. Made by ' + meta.generator + ' from ' + meta.source + '.';
  side.appendChild(note);

  const xOf = (time, width) => span > 0 ? (time - t0) / span * width : 0;
  const drawBase = (p) => {
    const dpr = window.devicePixelRatio || 1;
    const W = Math.max(1, Math.round(p.canvas.clientWidth * dpr)), H = Math.max(1, Math.round(p.canvas.clientHeight * dpr));
    p.canvas.width = W;
    p.canvas.height = H;
    const base = document.createElement('canvas');
    base.width = W;
    base.height = H;
    const g = base.getContext('2d');
    const yOf = (value) => H - (value - p.low) / (p.high - p.low) * H;
    if (p.low < 0 && p.high > 0) {
      g.strokeStyle = '#3a414d';
      g.setLineDash([4 * dpr, 4 * dpr]);
      g.beginPath();
      g.moveTo(0, yOf(0));
      g.lineTo(W, yOf(0));
      g.stroke();
      g.setLineDash([]);
    }
    for (const s of p.series) {
      g.fillStyle = s.color;
      g.strokeStyle = s.color;
      g.lineWidth = dpr;
      if (F > W / 2) {  // more frames than pixels: each pixel column spans the values of its frames
        const top = new Float64Array(W).fill(-Infinity), bottom = new Float64Array(W).fill(Infinity);
        for (let j = 0; j < F; ++j) {
          const x = Math.min(W - 1, Math.floor(xOf(t[j], W)));
          top[x] = Math.max(top[x], s.hi(j));
          bottom[x] = Math.min(bottom[x], s.lo(j));
          if (j > 0) {  // the line from the previous frame crosses the columns between
            const x0 = Math.min(W - 1, Math.floor(xOf(t[j - 1], W)));
            for (let c = x0 + 1; c < x; ++c) {
              top[c] = Math.max(top[c], s.hi(j - 1), s.hi(j));
              bottom[c] = Math.min(bottom[c], s.lo(j - 1), s.lo(j));
            }
          }
        }
        for (let x = 0; x < W; ++x) {
          if (!(top[x] >= bottom[x])) continue;
          const y0 = yOf(top[x]), y1 = yOf(bottom[x]);
          g.fillRect(x, y0 - dpr / 2, 1, Math.max(dpr, y1 - y0 + dpr));
        }
        continue;
      }
      let band = false;
      g.beginPath();
      for (let j = 0; j < F; ++j) {
        const x = xOf(t[j], W), y = yOf(s.hi(j));
        if (j === 0) g.moveTo(x, y); else g.lineTo(x, y);
        band = band || s.lo(j) !== s.hi(j);
      }
      if (band) {
        for (let j = F - 1; j >= 0; --j) g.lineTo(xOf(t[j], W), yOf(s.lo(j)));
        g.closePath();
        g.globalAlpha = 0.5;
        g.fill();
        g.globalAlpha = 1;
      }
      g.stroke();
    }
    p.base = base;
  };
  const drawPlot = (p, time) => {
    const g = p.canvas.getContext('2d');
    g.clearRect(0, 0, p.canvas.width, p.canvas.height);
    g.drawImage(p.base, 0, 0);
    const x = xOf(time, p.canvas.width);
    g.strokeStyle = '#ffffff';
    g.lineWidth = 1;
    g.beginPath();
    g.moveTo(x, 0);
    g.lineTo(x, p.canvas.height);
    g.stroke();
  };

  // Playing.
  const duration = 20;  // seconds of wall time for the whole run at speed 1
  const state = {frame: 0, playing: false, speed: 1, time: t0, rendered: 0, fps: 0};
  const playButton = document.getElementById('play');
  const scrub = document.getElementById('scrub');
  const timeText = document.getElementById('time');
  const counter = document.getElementById('counter');
  const speed = document.getElementById('speed');
  for (const s of [0.1, 0.25, 0.5, 1, 2, 5, 10, 50]) {
    const o = document.createElement('option');
    o.value = String(s);
    o.textContent = s + '×' + (s === 1 ? ' (' + duration + ' s)' : '');
    if (s === 1) o.selected = true;
    speed.appendChild(o);
  }
  scrub.max = String(F - 1);
  const frameAt = (time) => {  // the last frame with t ≤ time
    let a = 0, b = F - 1;
    if (time >= t[b]) return b;
    while (b - a > 1) {
      const m = (a + b) >> 1;
      if (t[m] <= time) a = m; else b = m;
    }
    return a;
  };
  const setPlaying = (on) => {
    state.playing = on;
    playButton.textContent = on ? 'Pause' : 'Play';
  };
  const seek = (j) => {
    state.frame = Math.max(0, Math.min(F - 1, Math.round(j)));
    state.time = t[state.frame];
  };
  function seekTime(e, c) {
    const r = c.getBoundingClientRect();
    seek(frameAt(t0 + (e.clientX - r.left) / r.width * span));
  }
  playButton.addEventListener('click', () => {
    if (!state.playing && state.frame === F - 1) seek(0);
    setPlaying(!state.playing);
  });
  speed.addEventListener('change', () => { state.speed = Number(speed.value); });
  scrub.addEventListener('input', () => seek(Number(scrub.value)));
  window.addEventListener('keydown', (e) => {
    if (e.target.tagName === 'SELECT') return;
    if (e.key === ' ') {
      playButton.click();
      e.preventDefault();
    } else if (e.key === 'ArrowRight' || e.key === 'ArrowLeft') {
      setPlaying(false);
      seek(state.frame + (e.key === 'ArrowRight' ? 1 : -1));
      e.preventDefault();
    }
  });

  const resize = () => {
    const W = canvas.clientWidth, H = canvas.clientHeight;
    if (renderer) renderer.setSize(W, H, false);
    renderer && renderer.setPixelRatio(window.devicePixelRatio || 1);
    camera.aspect = W / Math.max(1, H);
    camera.updateProjectionMatrix();
    for (const p of plots) drawBase(p);
  };
  window.addEventListener('resize', resize);
  resize();

  const show = () => {
    const j = state.frame;
    frame.quaternion.set(q[4 * j + 1], q[4 * j + 2], q[4 * j + 3], q[4 * j]);
    traceGeometry.setDrawRange(0, j + 1);
    if (rotorAngle)
      for (let r = 0; r < rotors.length; ++r) rotors[r].rotation.y = rotorAngle[j * rotors.length + r];
    tip.position.fromArray(tracePoints, 3 * j);
    if (omegaArrow) {
      const w = lab(j, bodyOmega(j), new THREE.Vector3());
      setArrow(omegaArrow, [w.x, w.y, w.z], omegaMax);
    }
    if (momentumArrow) {
      const m = lab(j, bodyMomentum(j), new THREE.Vector3());
      setArrow(momentumArrow, [m.x, m.y, m.z], momentumMax);
    }
    if (renderer) renderer.render(scene, camera);
    for (const p of plots) drawPlot(p, t[j]);
    scrub.value = String(j);
    timeText.textContent = 't = ' + format(t[j]) + ' of ' + format(tEnd);
  };

  let last = performance.now();
  const stamps = [];
  const tick = (now) => {
    const elapsed = Math.min(0.25, Math.max(0, (now - last) / 1000));
    last = now;
    if (state.playing) {
      state.time += elapsed * state.speed * span / duration;
      if (state.time >= tEnd) {
        state.time = tEnd;
        setPlaying(false);
      }
      state.frame = frameAt(state.time);
    }
    show();
    state.rendered += 1;
    stamps.push(now);
    while (stamps.length > 0 && stamps[0] < now - 1000) stamps.shift();
    state.fps = stamps.length;
    counter.textContent = 'frame ' + (state.frame + 1) + ' of ' + F + ' · ' + state.fps + ' fps';
    requestAnimationFrame(tick);
  };

  window.lgiView = {
    meta: meta,
    state: () => ({frame: state.frame, frames: F, time: t[state.frame], t_end: tEnd, time_text: timeText.textContent,
                   playing: state.playing, rendered: state.rendered, fps: state.fps, webgl: !!renderer,
                   antialias: !!renderer && !softwareGL}),
    play: () => setPlaying(true),
    pause: () => setPlaying(false),
    seek: (j) => { setPlaying(false); seek(j); },
    setSpeed: (s) => { state.speed = s; },
  };
  setPlaying(span > 0 && !/[#&]paused/.test(location.hash));
  requestAnimationFrame(tick);
})();
