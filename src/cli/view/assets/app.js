// nffrt view: the page's side of the WebSocket protocol (src/cli/view/protocol.rs),
// the camera controls and the ray-tree panel. No framework, no build step.
'use strict';

const token = new URLSearchParams(location.search).get('token') || '';
const $ = (id) => document.getElementById(id);
const body = document.body;
const picture = $('picture');
const pctx = picture.getContext('2d');
const overlay = $('overlay');
const octx = overlay.getContext('2d');

let ws = null;
let scene = null; // the last `scene` message
let camera = null; // {from, at, up, angle}: what the page asks for
let options = null; // {width, height, max_depth, spp, lens, soft_shadows, rough, integrator, shutter, accel, denoise}
let shownGen = 0; // newest generation drawn: older frames are dropped
let frames = 0;
let fullFrames = 0;
let cameraBlock = '';
let lastTree = null;
let treeCamera = null; // the page's camera when the pixel was clicked
let pending = false;
let animFrame = null; // the animation frame asked for (null: the scene as loaded)
let playing = null; // while playing: {t0, f0, gen, advanced}

// --- vectors -------------------------------------------------------------
const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const mul = (a, s) => [a[0] * s, a[1] * s, a[2] * s];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const len = (a) => Math.sqrt(dot(a, a));
const norm = (a) => mul(a, 1 / len(a));
// Rodrigues: `v` turned by `angle` about the unit axis `k`.
const rotate = (v, k, angle) => {
  const c = Math.cos(angle), s = Math.sin(angle);
  return add(add(mul(v, c), mul(cross(k, v), s)), mul(k, dot(k, v) * (1 - c)));
};
const vec = (v) => (v && 'x' in v ? [v.x, v.y, v.z] : v);
const fmt = (v) => '(' + vec(v).map((x) => (x + 0).toFixed(4)).join(', ') + ')';
// A material number as written (f32 values arrive widened to f64).
const num = (x) => Number(x.toPrecision(7));

// --- connection ----------------------------------------------------------
function connect() {
  ws = new WebSocket(`ws://${location.host}/ws?token=${encodeURIComponent(token)}`);
  ws.binaryType = 'arraybuffer';
  ws.onmessage = (ev) => (typeof ev.data === 'string' ? onText(JSON.parse(ev.data)) : onBinary(ev.data));
  ws.onclose = () => { $('status').textContent = 'disconnected: is nffrt view still running?'; };
}

function send(msg) {
  if (ws && ws.readyState === WebSocket.OPEN) ws.send(JSON.stringify(msg));
}

// At most one render request per animation frame, with the latest state.
function requestRender() {
  if (pending || !camera) return;
  pending = true;
  requestAnimationFrame(() => {
    pending = false;
    send(animFrame === null ? { type: 'render', camera, options } : { type: 'render', camera, options, frame: animFrame });
  });
}

function onText(msg) {
  switch (msg.type) {
    case 'scene': return onScene(msg);
    case 'view':
      if (playing && msg.frame === animFrame) Object.assign(playing, { gen: msg.gen, advanced: false });
      cameraBlock = msg.camera_block;
      $('camera-block').textContent = cameraBlock;
      if (msg.reason === 'reload') {
        camera = msg.camera;
        options = msg.options;
        showOptions();
      }
      return;
    case 'load_error':
      $('load-error').hidden = false;
      $('load-error').textContent = msg.message + '\n(the last good picture stays; save the file again to retry)';
      body.dataset.loadError = msg.message;
      return;
    case 'error': return flash(msg.message);
    case 'ray_tree': return showTree(msg);
    case 'reference': return onReferenceMessage(msg);
  }
}

function onScene(msg) {
  const first = scene === null;
  scene = msg;
  $('name').textContent = msg.name;
  $('load-error').hidden = true;
  delete body.dataset.loadError;
  body.dataset.version = msg.version;
  const w = msg.warnings;
  $('warnings-box').hidden = w.length === 0;
  $('warnings-summary').textContent = `${w.length} warning${w.length === 1 ? '' : 's'}`;
  $('warnings').replaceChildren(...w.map((t) => Object.assign(document.createElement('li'), { textContent: t })));
  $('lens').disabled = !msg.has_lens;
  $('soft').disabled = !msg.has_area_lights;
  $('rough').disabled = !msg.has_roughness;
  $('shutter-open').disabled = $('shutter-close').disabled = !msg.has_motion;
  $('denoise').disabled = !msg.denoiser;
  $('denoise').parentElement.title = msg.denoiser || msg.denoiser_help || '';
  const lim = msg.limits;
  for (const [id, max] of [['width', lim.max_side], ['height', lim.max_side], ['depth', lim.max_depth], ['spp', lim.max_spp]]) {
    $(id).dataset.max = max;
  }
  showAnimation(msg.animation, first);
  if (first) {
    camera = frameCamera() || msg.camera;
    options = msg.options;
    showOptions();
    requestRender();
  } else {
    flash(`reloaded (version ${msg.version})`);
    // The ray tree was of the old scene.
    lastTree = null;
    drawRays();
    $('tree').replaceChildren();
    $('tree-hint').hidden = false;
  }
}

function onBinary(buffer) {
  const n = new DataView(buffer).getUint32(0, true);
  const header = JSON.parse(new TextDecoder().decode(new Uint8Array(buffer, 4, n)));
  const payload = new Uint8Array(buffer, 4 + n);
  if (header.kind === 'png') return download(payload);
  if (header.kind === 'reference' || header.kind === 'flip') return onCompareBinary(header, payload);
  if (header.gen < shownGen) return;
  shownGen = header.gen;
  draw(header, payload);
  if (playing && header.gen === playing.gen && !playing.advanced) playOn();
  frames += 1;
  if (header.stride === 1) fullFrames += 1;
  body.dataset.frame = frames;
  body.dataset.fullFrames = fullFrames;
  body.dataset.gen = header.gen;
  body.dataset.stride = header.stride;
  body.dataset.samples = header.samples;
  body.dataset.complete = header.complete;
  body.dataset.denoised = header.denoised;
  const c = scene ? scene.counts : null;
  const mrays = header.rays / Math.max(header.ms, 1e-3) / 1e3;
  // Samples per pixel per second: how fast the running average converges.
  const rate = header.samples / Math.max(header.ms / 1e3, 1e-3);
  const count = (n, word) => `${n} ${word}${n === 1 ? '' : 's'}`;
  $('status').textContent = [
    header.stride > 1 ? `preview 1/${header.stride}` : `samples ${header.samples}/${header.target}${header.denoised ? ' denoised' : ''}`,
    header.stride > 1 ? '' : `${rate < 10 ? rate.toFixed(2) : rate.toFixed(1)} samples/s`,
    `${mrays.toFixed(1)} Mrays/s`,
    `${(header.ms / 1e3).toFixed(2)} s`,
    `${header.width}×${header.height}`,
    c ? [count(c.primitives, 'primitive'), count(c.lights, 'light'), count(c.materials, 'material')].join(', ') : '',
  ].filter((part) => part !== '').join(' · ');
}

// Draws a frame, unless the reference or the FLIP map is shown instead
// (compare.js), which keeps it for when the live picture is shown again.
function draw(h, rgb) {
  lastLive = { h, rgb };
  const sameSize = picture.width === h.width && picture.height === h.height;
  if (sameSize && compareView !== 'live' && compareDraw()) return drawRays();
  drawLive(h, rgb);
}

// Draws a live frame: full size, or a preview whose pixels stand for stride² blocks.
function drawLive(h, rgb) {
  const cols = Math.ceil(h.width / h.stride), rows = Math.ceil(h.height / h.stride);
  if (picture.width !== h.width || picture.height !== h.height) {
    picture.width = overlay.width = h.width;
    picture.height = overlay.height = h.height;
    layout();
  }
  const image = new ImageData(cols, rows);
  for (let i = 0, j = 0; i < rgb.length; i += 3, j += 4) {
    image.data[j] = rgb[i];
    image.data[j + 1] = rgb[i + 1];
    image.data[j + 2] = rgb[i + 2];
    image.data[j + 3] = 255;
  }
  if (h.stride === 1) {
    pctx.putImageData(image, 0, 0);
  } else {
    const small = new OffscreenCanvas(cols, rows);
    small.getContext('2d').putImageData(image, 0, 0);
    pctx.imageSmoothingEnabled = false;
    pctx.drawImage(small, 0, 0, cols * h.stride, rows * h.stride);
  }
  drawRays();
}

function download(png) {
  const a = document.createElement('a');
  a.href = URL.createObjectURL(new Blob([png], { type: 'image/png' }));
  a.download = (scene ? scene.name.split(/[\\/]/).pop().replace(/\.[^.]*$/, '') : 'nffrt') + '.png';
  a.click();
  setTimeout(() => URL.revokeObjectURL(a.href), 10000);
}

function flash(text) {
  $('message').textContent = text;
  clearTimeout(flash.timer);
  flash.timer = setTimeout(() => { $('message').textContent = ''; }, 5000);
}

// --- controls --------------------------------------------------------------
const fields = { width: 'width', height: 'height', depth: 'max_depth', spp: 'spp' };
const labels = { width: 'width', height: 'height', depth: 'max depth', spp: 'target spp' };

function showOptions() {
  for (const [id, key] of Object.entries(fields)) $(id).value = options[key];
  $('lens').checked = options.lens;
  $('soft').checked = options.soft_shadows;
  $('rough').checked = options.rough;
  $('integrator').value = options.integrator;
  $('accel').value = options.accel;
  $('shutter-open').value = options.shutter[0];
  $('shutter-close').value = options.shutter[1];
  $('denoise').checked = !!options.denoise;
}

// Says why a setting was refused (and the old value kept), or clears the message.
function optionsError(text) {
  $('options-error').hidden = !text;
  $('options-error').textContent = text || '';
  if (text) body.dataset.optionsError = text;
  else delete body.dataset.optionsError;
}

// Why field `id` cannot take `text`, or null. The limits are the server's, sent with
// the scene message; it checks them again. (Text fields, not number fields: those
// swallow what is no number, and the page could not say what it refused.)
function refusal(id, text) {
  const max = Number($(id).dataset.max);
  const v = /^\s*\d+\s*$/.test(text) ? Number(text) : NaN;
  if (!Number.isInteger(v) || v < 1 || v > max) return `a whole number from 1 to ${max}`;
  if (id === 'width' || id === 'height') {
    const [w, h] = id === 'width' ? [v, options.height] : [options.width, v];
    const most = scene.limits.max_pixels;
    if (w * h > most) return `${w} × ${h} = ${w * h} pixels, more than ${most}`;
  }
  return null;
}

for (const [id, key] of Object.entries(fields)) {
  $(id).addEventListener('change', () => {
    if (!options || !scene) return;
    const typed = $(id).value;
    const why = refusal(id, typed);
    if (why) {
      optionsError(`${labels[id]}: ${typed.trim() === '' ? 'nothing' : typed.trim()} refused, ${why}; kept ${options[key]}`);
      $(id).value = options[key];
      return;
    }
    optionsError(null);
    options = { ...options, [key]: Number(typed) };
    requestRender();
  });
}
$('lens').addEventListener('change', () => { options = { ...options, lens: $('lens').checked }; requestRender(); });
$('soft').addEventListener('change', () => { options = { ...options, soft_shadows: $('soft').checked }; requestRender(); });
$('rough').addEventListener('change', () => { options = { ...options, rough: $('rough').checked }; requestRender(); });
$('denoise').addEventListener('change', () => { options = { ...options, denoise: $('denoise').checked }; requestRender(); });
$('integrator').addEventListener('change', () => { options = { ...options, integrator: $('integrator').value }; requestRender(); });
// The same picture with each structure; the status line's samples per second differ.
$('accel').addEventListener('change', () => { options = { ...options, accel: $('accel').value }; requestRender(); });
// The shutter's two times: numbers, the first no later than the second.
for (const [id, k] of [['shutter-open', 0], ['shutter-close', 1]]) {
  $(id).addEventListener('change', () => {
    if (!options) return;
    const typed = $(id).value.trim();
    const v = /^[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$/.test(typed) ? Number(typed) : NaN;
    const shutter = [...options.shutter];
    shutter[k] = v;
    const why = !Number.isFinite(v) || Math.abs(v) >= 1e6 ? 'a number (below 1e6)'
      : shutter[0] > shutter[1] ? 'the shutter must open no later than it closes' : null;
    if (why) {
      optionsError(`shutter: ${typed === '' ? 'nothing' : typed} refused, ${why}; kept ${options.shutter[k]}`);
      $(id).value = options.shutter[k];
      return;
    }
    optionsError(null);
    options = { ...options, shutter };
    requestRender();
  });
}
$('actual').addEventListener('change', layout);
window.addEventListener('resize', layout);

// The picture's size on screen: fitted to the stage's width and the window's height
// below the stage's top, aspect kept (scaled up or down; pixels stay sharp), or 1:1,
// one picture pixel per device pixel, the stage scrolling when it is larger. The
// overlay takes the same size; clicks map back through the drawn size (pixelAt).
function layout() {
  const stage = $('stage');
  const actual = $('actual').checked;
  const room = window.innerHeight - (stage.getBoundingClientRect().top + window.scrollY) - 16;
  const scale = actual
    ? 1 / (window.devicePixelRatio || 1)
    : Math.max(Math.min(stage.clientWidth / picture.width, room / picture.height), 1e-3);
  for (const c of [picture, overlay]) {
    c.style.width = `${picture.width * scale}px`;
    c.style.height = `${picture.height * scale}px`;
  }
  stage.classList.toggle('actual', actual);
  stage.style.maxHeight = actual ? `${Math.max(room, 100)}px` : '';
  body.dataset.scale = scale;
  body.dataset.actual = actual;
}

function reset() {
  if (!scene) return;
  camera = frameCamera() || scene.camera;
  requestRender();
}
$('reset').addEventListener('click', reset);
$('save').addEventListener('click', () => send({ type: 'png' }));
$('copy').addEventListener('click', async () => {
  try {
    await navigator.clipboard.writeText(cameraBlock);
    flash('camera block copied');
  } catch (e) {
    flash('select the camera block below and copy it');
  }
});

// The camera frame: forward, right, true up.
function frame(c) {
  const f = norm(sub(c.at, c.from));
  const r = norm(cross(f, c.up));
  return { f, r, u: cross(r, f) };
}

function orbit(dx, dy) {
  const up = norm(camera.up);
  let offset = sub(camera.from, camera.at);
  offset = rotate(offset, up, -dx * 0.01);
  const { r } = frame(camera);
  const turned = rotate(offset, r, -dy * 0.01);
  // Stay off the poles, where `up` would be parallel to the view.
  const cos = dot(norm(turned), up);
  if (Math.abs(cos) < 0.995) offset = turned;
  camera = { ...camera, from: add(camera.at, offset) };
  requestRender();
}

function pan(dx, dy) {
  const { r, u } = frame(camera);
  const pixel = (2 * len(sub(camera.at, camera.from)) * Math.tan((camera.angle * Math.PI) / 360)) / options.height;
  const move = add(mul(r, -dx * pixel), mul(u, dy * pixel));
  camera = { ...camera, from: add(camera.from, move), at: add(camera.at, move) };
  requestRender();
}

function dolly(steps) {
  const offset = mul(sub(camera.from, camera.at), Math.exp(steps * 0.1));
  if (len(offset) > 1e-6) {
    camera = { ...camera, from: add(camera.at, offset) };
    requestRender();
  }
}

// Pointer position in picture pixels.
function pixelAt(ev) {
  const rect = picture.getBoundingClientRect();
  return [
    Math.floor(((ev.clientX - rect.left) * picture.width) / rect.width),
    Math.floor(((ev.clientY - rect.top) * picture.height) / rect.height),
  ];
}

let drag = null;
picture.addEventListener('contextmenu', (ev) => ev.preventDefault());
picture.addEventListener('pointerdown', (ev) => {
  picture.setPointerCapture(ev.pointerId);
  drag = { x: ev.clientX, y: ev.clientY, moved: 0, pan: ev.button === 2 || ev.shiftKey, start: pixelAt(ev) };
  picture.classList.add('dragging');
});
picture.addEventListener('pointermove', (ev) => {
  if (!drag || !camera) return;
  const scale = picture.width / picture.getBoundingClientRect().width;
  const dx = (ev.clientX - drag.x) * scale, dy = (ev.clientY - drag.y) * scale;
  drag.x = ev.clientX;
  drag.y = ev.clientY;
  drag.moved += Math.abs(dx) + Math.abs(dy);
  if (drag.moved > 3) (drag.pan ? pan : orbit)(dx, dy);
});
picture.addEventListener('pointerup', () => {
  picture.classList.remove('dragging');
  if (drag && drag.moved <= 3) {
    const [x, y] = drag.start;
    treeCamera = camera;
    send({ type: 'pixel', x, y });
  }
  drag = null;
});
picture.addEventListener('wheel', (ev) => {
  ev.preventDefault();
  if (camera) dolly(Math.sign(ev.deltaY));
}, { passive: false });

window.addEventListener('keydown', (ev) => {
  if (!camera || ev.target instanceof HTMLInputElement) return;
  const step = 10;
  const keys = {
    ArrowLeft: () => (ev.shiftKey ? pan(-step, 0) : orbit(-step, 0)),
    ArrowRight: () => (ev.shiftKey ? pan(step, 0) : orbit(step, 0)),
    ArrowUp: () => (ev.shiftKey ? pan(0, -step) : orbit(0, -step)),
    ArrowDown: () => (ev.shiftKey ? pan(0, step) : orbit(0, step)),
    '+': () => dolly(-1), '=': () => dolly(-1), '-': () => dolly(1), PageUp: () => dolly(-1), PageDown: () => dolly(1),
    r: reset, R: reset,
  };
  if (keys[ev.key]) {
    ev.preventDefault();
    keys[ev.key]();
  }
});

// --- the ray tree ----------------------------------------------------------
function el(tag, cls, text) {
  const e = document.createElement(tag);
  if (cls) e.className = cls;
  if (text !== undefined) e.textContent = text;
  return e;
}

function outcome(o) {
  if (o === 'Behind') return ['behind the surface (no shadow ray)', 'shadowed'];
  if (o === 'Shadowed') return ['shadowed', 'shadowed'];
  return ['adds ' + fmt(o.Lit), 'lit'];
}

// Whether the tree on show is of a P3F scene (its materials have specular colours).
let treeIsP3f = false;

function rayNode(node, kinds, lights, title, open = true) {
  const box = el('details');
  box.open = open;
  const h = node.hit;
  const summary = el('summary', h ? 'hit' : 'miss');
  if (h) {
    summary.textContent = `${title}: hit ${kinds[h.kind] || h.kind} at line ${h.line}, t = ${h.t.toFixed(4)}, ${h.entering ? 'entering' : 'leaving'}`;
    summary.dataset.line = h.line;
  } else {
    summary.textContent = node.sky
      ? `${title}: miss, skybox face ${node.sky.face}, texel (${node.sky.column}, ${node.sky.row}) from its bottom-left: ${fmt(node.color)}`
      : `${title}: miss, background ${fmt(node.color)}`;
  }
  box.append(summary);
  const fact = (t, cls) => box.append(el('div', 'fact' + (cls ? ' ' + cls : ''), t));
  fact(`from ${fmt(node.origin)} dir ${fmt(node.dir)}`);
  if (node.smooth_dir) {
    const cos = Math.min(1, Math.max(-1, dot(vec(node.smooth_dir), vec(node.dir))));
    fact(`rough: drawn ${(Math.acos(cos) * 180 / Math.PI).toFixed(2)}° from the smooth direction ${fmt(node.smooth_dir)}`);
  }
  if (h) {
    fact(`point ${fmt(h.point)} normal ${fmt(h.normal)}`);
    if (h.absorbed) fact(`inside the glass: ${fmt(h.absorbed)} of the light left after the way here (Beer–Lambert)`);
    const [index, m] = h.material;
    const specular = treeIsP3f ? ` specular ${fmt(m.specular)}` : '';
    fact(`material #${index}: colour ${fmt(m.color)} Kd ${num(m.kd)}${specular} Ks ${num(m.ks)} shine ${num(m.shine)} T ${num(m.t)} ior ${num(m.ior)}`);
    fact(`ambient ${fmt(h.ambient)}`);
    h.lights.forEach((rec, k) => {
      const at = lights[k] ? ' at ' + fmt(lights[k]) : '';
      if (rec.Point !== undefined) {
        const [text, cls] = outcome(rec.Point);
        fact(`light ${k + 1}${at}: ${text}`, cls);
      } else {
        const a = rec.Area.outcome;
        fact(`area light ${k + 1}${at}: ${a.samples} points, ${a.samples - a.shadowed - a.behind} lit, ${a.shadowed} shadowed, ${a.behind} behind: adds ${fmt(a.contribution)}`);
      }
    });
    for (const [kind, weight, child] of h.children) {
      const w = vec(weight);
      const name = kind === 'Refraction' ? 'refraction' : kind === 'Reflection' ? 'reflection' : 'reflection (total internal reflection)';
      box.append(rayNode(child, kinds, lights, `${name}, weight ${w[0] === w[1] && w[1] === w[2] ? num(w[0]) : fmt(w)}`));
    }
    fact(`= colour ${fmt(node.color)}`, 'value');
  }
  return box;
}

// One path of the path tracer as a list of its events (src/render/path_log.rs).
function pathNode(steps, kinds, title, open) {
  const box = el('details');
  box.open = open;
  const vertices = steps.filter((s) => s.Vertex).length;
  const escaped = steps.find((s) => s.Escape);
  box.append(el('summary', vertices ? 'hit' : 'miss', `${title}: ${vertices} vert${vertices === 1 ? 'ex' : 'ices'}${escaped ? ', then escapes' : ''}`));
  const fact = (t, cls) => box.append(el('div', 'fact' + (cls ? ' ' + cls : ''), t));
  const w = (x) => num(x);
  let n = 0;
  for (const step of steps) {
    const [kind, e] = Object.entries(step)[0];
    if (kind === 'Vertex') {
      n += 1;
      fact(`vertex ${n}: ${kinds[e.kind] || e.kind} at line ${e.line}, material #${e.material}, t = ${e.t.toFixed(4)}, ${e.entering ? 'entering' : 'leaving'}; point ${fmt(e.point)} normal ${fmt(e.normal)}; throughput ${fmt(e.throughput)}`, 'value');
    } else if (kind === 'Emitted') {
      fact(`emits ${fmt(e.radiance)}, MIS weight ${w(e.weight)}`, 'lit');
    } else if (kind === 'Light') {
      fact(e.blocked
        ? `light sample at ${fmt(e.point)}: blocked`
        : `light sample at ${fmt(e.point)}: adds ${fmt(e.contribution)}, MIS weight ${w(e.weight)}`, e.blocked ? 'shadowed' : 'lit');
    } else if (kind === 'Bsdf') {
      const how = e.delta ? 'specular' : `pdf ${w(e.pdf)}`;
      fact(`BSDF sample: ${e.transmitted ? 'through' : 'off'} the surface, dir ${fmt(e.dir)}, f·cos/pdf ${fmt(e.weight)} (${how}); throughput ${fmt(e.throughput)}`);
    } else if (kind === 'Escape') {
      fact(`escapes along ${fmt(e.dir)}: sees ${fmt(e.radiance)} with throughput ${fmt(e.throughput)}`);
    } else {
      fact(`${kind}: ${JSON.stringify(e)}`);
    }
  }
  return box;
}

function showTree(msg) {
  const t = msg.trace;
  treeIsP3f = t.dialect !== 'Nff';
  const q = (v) => Math.round(Math.min(Math.max(v, 0), 1) * 255);
  const value = vec(t.value);
  const tree = $('tree');
  tree.replaceChildren(
    el('div', 'value', `pixel (${t.x}, ${t.y}) of ${t.opts.width}x${t.opts.height}: value ${fmt(value)} → 8-bit (${value.map(q).join(', ')})`),
    el('div', 'fact', `rays: ${t.stats.eye_rays} eye, ${t.stats.reflection_rays} reflection, ${t.stats.refraction_rays} refraction, ${t.stats.shadow_rays} shadow (${t.stats.shadow_blocked} blocked)`),
    el('div', 'help', t.lens
      ? 'Over the picture: a yellow dot where each eye ray hits (each leaves its own point of the lens, so they spread over the out-of-focus area), then reflections (cyan), refractions (magenta) and shadow rays (dashed).'
      : 'Over the picture: a yellow dot where the eye ray hits, then reflections (cyan), refractions (magenta) and shadow rays (dashed).'),
  );
  t.samples.forEach(([sample, node], k) => {
    const raster = sample.raster;
    const lens = t.lens ? `, lens (${sample.lens[0].toFixed(3)}, ${sample.lens[1].toFixed(3)})` : '';
    const time = t.motion ? `, time ${sample.time.toFixed(3)} of the shutter` : '';
    const title = `eye ray ${k + 1} of ${t.samples.length} through raster (${raster[0].toFixed(3)}, ${raster[1].toFixed(3)})${lens}${time}`;
    // The first eye ray open, the others folded. A path tracer's trace is a list of
    // the path's events, Whitted's a tree.
    tree.append(Array.isArray(node)
      ? pathNode(node, msg.kinds, title, k === 0)
      : rayNode(node, msg.kinds, t.lights, title, k === 0));
  });
  $('tree-hint').hidden = true;
  lastTree = msg;
  drawRays();
  body.dataset.trees = Number(body.dataset.trees) + 1;
}

// Draws the last ray tree over the picture: a dot where each eye ray hits (an eye
// ray itself, seen from the eye, is a point; with a lens it leaves from its own
// point of the lens, and the line from there, cut at the camera plane, would only
// fan across the picture), segments between later hits (cut at the camera plane),
// dashed shadow rays to point lights (green lit, red blocked), and a ring at the
// clicked pixel while the camera has not moved.
function drawRays() {
  octx.clearRect(0, 0, overlay.width, overlay.height);
  const msg = lastTree;
  if (!msg || !camera) return;
  // Projected with the page's camera: the rays stay on their objects as it moves.
  const c = camera, W = overlay.width, H = overlay.height;
  // (The camera object is replaced whenever the camera moves.)
  const sameView = c === treeCamera && msg.trace.opts.width === W && msg.trace.opts.height === H;
  const { f, r, u } = frame(c);
  const spans = msg.angle_spans_edges ? H : Math.max(H, 2) - 1;
  const pitch = (2 * Math.tan((c.angle * Math.PI) / 360)) / spans;
  const near = 1e-4 * len(sub(c.at, c.from));
  const depth = (p) => dot(sub(p, c.from), f);
  const project = (p) => {
    const d = sub(p, c.from), z = dot(d, f);
    return [W / 2 + dot(d, r) / z / pitch, H / 2 - dot(d, u) / z / pitch];
  };
  // The segment p-q in world space, the part in front of the camera.
  const segment = (p, q, colour, dash) => {
    let [zp, zq] = [depth(p), depth(q)];
    if (zp < near && zq < near) return;
    if (zp < near) [p, q, zp, zq] = [q, p, zq, zp];
    if (zq < near) q = add(p, mul(sub(q, p), (zp - near) / (zp - zq)));
    const [a, b] = [project(p), project(q)];
    octx.strokeStyle = colour;
    octx.setLineDash(dash || []);
    octx.beginPath();
    octx.moveTo(a[0], a[1]);
    octx.lineTo(b[0], b[1]);
    octx.stroke();
  };
  const far = len(sub(c.at, c.from)) * 1e3;
  const mark = (p, colour) => {
    if (depth(p) < near) return;
    const [x, y] = project(p);
    octx.fillStyle = colour;
    octx.beginPath();
    octx.arc(x, y, Math.max(2, W / 200), 0, 2 * Math.PI);
    octx.fill();
  };
  const walk = (node, colour, eye) => {
    const origin = vec(node.origin);
    const end = node.hit ? vec(node.hit.point) : add(origin, mul(vec(node.dir), far));
    if (eye) {
      if (node.hit) mark(end, colour);
    } else {
      segment(origin, end, colour);
    }
    if (!node.hit) return;
    node.hit.lights.forEach((rec, k) => {
      const light = msg.trace.lights[k];
      if (rec.Point === undefined || rec.Point === 'Behind' || !light) return;
      segment(end, vec(light), rec.Point === 'Shadowed' ? '#ff8a80' : '#a5d6a7', [3, 3]);
    });
    for (const [kind, , child] of node.hit.children) walk(child, kind === 'Refraction' ? '#e040fb' : '#4dd0e1', false);
  };
  // A path: a dot at its first vertex, segments between the later ones (cyan off
  // a surface, magenta through it), dashed light samples (green lit, red blocked).
  const walkPath = (steps) => {
    let last = null, through = false;
    for (const step of steps) {
      const [kind, e] = Object.entries(step)[0];
      if (kind === 'Vertex') {
        const p = vec(e.point);
        if (last) segment(last, p, through ? '#e040fb' : '#4dd0e1');
        else mark(p, '#ffd54f');
        last = p;
      } else if (kind === 'Bsdf') {
        through = e.transmitted;
      } else if (kind === 'Light' && last) {
        segment(last, vec(e.point), e.blocked ? '#ff8a80' : '#a5d6a7', [3, 3]);
      } else if (kind === 'Escape' && last) {
        segment(last, add(last, mul(vec(e.dir), far)), through ? '#e040fb' : '#4dd0e1');
      }
    }
  };
  octx.lineWidth = Math.max(1.5, W / 400);
  for (const [sample, node] of msg.trace.samples) {
    const raster = sample.raster;
    if (Array.isArray(node)) walkPath(node);
    else walk(node, '#ffd54f', true);
    if (!sameView) continue;
    octx.setLineDash([]);
    octx.strokeStyle = '#ffd54f';
    octx.beginPath();
    octx.arc(raster[0], raster[1], Math.max(4, W / 100), 0, 2 * Math.PI);
    octx.stroke();
  }
}

// --- animation (AFF scenes) -------------------------------------------
// The frame is in the URL (`frame=N`), so a reload shows the same one. Changing
// frames moves the camera to the new frame's (the file's keyframes) unless the
// user has moved it off the old frame's.

// The camera of the frame asked for, when the file keys it.
function frameCamera() {
  const cams = scene && scene.animation ? scene.animation.cameras : [];
  return animFrame !== null && cams.length > animFrame ? cams[animFrame] : null;
}

function showAnimation(anim, first) {
  const animated = !!anim && anim.frames > 1;
  $('animation').hidden = !animated;
  if (!animated) {
    stop();
    animFrame = null;
  } else {
    const asked = first ? Number.parseInt(new URLSearchParams(location.search).get('frame'), 10) : animFrame;
    animFrame = Math.min(Number.isInteger(asked) && asked >= 0 ? asked : 0, anim.frames - 1);
    $('frame-slider').max = anim.frames - 1;
  }
  showFrame();
}

function showFrame() {
  body.dataset.animFrame = animFrame === null ? 'none' : animFrame;
  const url = new URL(location.href);
  if (animFrame === null) {
    url.searchParams.delete('frame');
  } else {
    const a = scene.animation;
    $('frame-slider').value = animFrame;
    $('frame-label').textContent = `${animFrame} / ${a.frames - 1} · time ${num(a.start + animFrame * a.step)}`;
    url.searchParams.set('frame', animFrame);
  }
  history.replaceState(history.state, '', url);
}

function setFrame(n) {
  if (animFrame === null || n === animFrame) return;
  const same = (a, b) => a && b && JSON.stringify(a) === JSON.stringify(b);
  const before = frameCamera();
  animFrame = n;
  const after = frameCamera();
  if (after && (!before || same(camera, before))) camera = after;
  showFrame();
  requestRender();
}

// Frames per second: one frame per step of the file's time, 1 to 60.
function fps() {
  const step = scene.animation.step;
  return step > 0 ? Math.min(Math.max(1 / step, 1), 60) : 10;
}

// The first picture of the frame shown while playing has come: the next frame is
// the one the clock is at (frames skipped when rendering is slower), no sooner
// than one frame time after the last; past the end, the animation starts over.
function playOn() {
  playing.advanced = true;
  const now = performance.now(), period = 1000 / fps();
  let next = Math.max(animFrame + 1, playing.f0 + Math.floor((now - playing.t0) / period));
  if (next >= scene.animation.frames) {
    next = 0;
    Object.assign(playing, { t0: now + period, f0: 0 });
  }
  const due = playing.t0 + (next - playing.f0) * period;
  playing.timer = setTimeout(() => setFrame(next), Math.max(0, due - now));
}

function play() {
  if (animFrame === null) return;
  playing = { t0: performance.now(), f0: animFrame, gen: -1, advanced: true };
  $('play').textContent = 'Pause';
  body.dataset.playing = 'true';
  // The frame shown has its pictures already: go on at once.
  playOn();
}

// Paused, the frame shown refines as a still scene does (its generation goes on).
function stop() {
  if (playing) clearTimeout(playing.timer);
  playing = null;
  $('play').textContent = 'Play';
  body.dataset.playing = 'false';
}

$('play').addEventListener('click', () => (playing ? stop() : play()));
$('frame-slider').addEventListener('input', (ev) => {
  stop();
  setFrame(Number(ev.target.value));
});

connect();
