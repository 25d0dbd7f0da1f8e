// nffrt view: the reference picture beside the live one. It comes from
// `--reference` or the file picker (sent to the server as a binary message); the
// page flips between the live picture (A) and the reference (B), shows the FLIP
// error map of the last finished pass, and plots FLIP's mean against the samples
// per pixel as they accumulate. Loaded after app.js, whose globals it shares.
'use strict';

let reference = null; // {name, width, height, mode, rgb}
let flipMap = null; // {gen, width, height, samples, mean, denoised, rgb}
let scores = []; // [{samples, mean, denoised}] of the generation shown
let scoresGen = 0;
let compareView = 'live'; // 'live' | 'reference' | 'flip'
let lastLive = null; // {h, rgb}: the last live frame drawn

// A `reference` text message: the picture's name, size and FLIP's mode.
function onReferenceMessage(msg) {
  reference = { ...msg, rgb: null };
  flipMap = null;
  scores = [];
  $('reference-name').textContent = `${msg.name}: ${msg.width}×${msg.height}, ${msg.mode === 'hdr' ? 'HDR-FLIP (float values)' : 'LDR-FLIP (as shown)'}`;
  $('view-ab').disabled = false;
  $('show-flip').disabled = false;
  body.dataset.reference = `${msg.width}x${msg.height}`;
  body.dataset.scores = 0;
  plot();
}

// A binary `reference` (its 8-bit pixels) or `flip` (a pass's error map) message.
function onCompareBinary(header, payload) {
  if (header.kind === 'reference') {
    if (reference) reference.rgb = payload.slice();
  } else if (header.kind === 'flip') {
    if (header.gen < shownGen) return;
    if (header.gen !== scoresGen) {
      scoresGen = header.gen;
      scores = [];
    }
    flipMap = { ...header, rgb: payload.slice() };
    scores.push({ samples: header.samples, mean: header.mean, denoised: header.denoised });
    body.dataset.scores = Number(body.dataset.scores) + 1;
    body.dataset.flipMean = header.mean;
    $('score').textContent = `FLIP ${header.mean.toFixed(4)} at ${header.samples} spp${header.denoised ? ' (denoised)' : ''}`;
    plot();
  }
  showCompareView();
}

// Draws the reference or the FLIP map over the picture, if one of the picture's
// size is there; true if it did.
function compareDraw() {
  const shown = compareView === 'reference' ? reference : compareView === 'flip' ? flipMap : null;
  if (!shown || !shown.rgb || shown.width !== picture.width || shown.height !== picture.height) return false;
  const image = new ImageData(shown.width, shown.height);
  for (let i = 0, j = 0; i < shown.rgb.length; i += 3, j += 4) {
    image.data[j] = shown.rgb[i];
    image.data[j + 1] = shown.rgb[i + 1];
    image.data[j + 2] = shown.rgb[i + 2];
    image.data[j + 3] = 255;
  }
  pctx.putImageData(image, 0, 0);
  return true;
}

// Shows the current view: the reference or the map when there is one to show,
// else the last live frame.
function showCompareView() {
  const drawn = compareView !== 'live' && compareDraw();
  body.dataset.view = drawn ? compareView : 'live';
  $('view-ab').textContent = compareView === 'reference' ? 'A/B: show the live picture (B)' : 'A/B: show the reference (B)';
  $('show-flip').checked = compareView === 'flip';
  if (!drawn && lastLive) drawLive(lastLive.h, lastLive.rgb);
}

function setCompareView(view) {
  compareView = view;
  showCompareView();
}

$('view-ab').addEventListener('click', () => setCompareView(compareView === 'reference' ? 'live' : 'reference'));
$('show-flip').addEventListener('change', () => setCompareView($('show-flip').checked ? 'flip' : 'live'));
window.addEventListener('keydown', (ev) => {
  if (!reference || ev.target instanceof HTMLInputElement) return;
  if (ev.key === 'b' || ev.key === 'B') setCompareView(compareView === 'reference' ? 'live' : 'reference');
  else if (ev.key === 'f' || ev.key === 'F') setCompareView(compareView === 'flip' ? 'live' : 'flip');
});

// The picked file goes to the server as one binary message: a 4-byte length, a
// JSON header naming it, then the file's bytes.
$('reference-file').addEventListener('change', async () => {
  const file = $('reference-file').files[0];
  if (!file || !ws || ws.readyState !== WebSocket.OPEN) return;
  const header = new TextEncoder().encode(JSON.stringify({ kind: 'reference', name: file.name }));
  const bytes = new Uint8Array(await file.arrayBuffer());
  const message = new Uint8Array(4 + header.length + bytes.length);
  new DataView(message.buffer).setUint32(0, header.length, true);
  message.set(header, 4);
  message.set(bytes, 4 + header.length);
  ws.send(message);
});

// FLIP's mean against the samples per pixel (log2 scale) of this generation's passes.
function plot() {
  const c = $('plot');
  const g = c.getContext('2d');
  const W = c.width, H = c.height, left = 44, bottom = 22, top = 8, right = 8;
  g.clearRect(0, 0, W, H);
  g.fillStyle = '#9aa0a6';
  g.strokeStyle = '#444';
  g.font = '11px system-ui, sans-serif';
  g.strokeRect(left, top, W - left - right, H - top - bottom);
  if (scores.length === 0) {
    g.fillText('FLIP against samples: no measure yet', left + 6, top + 16);
    return;
  }
  const maxS = Math.max(...scores.map((s) => s.samples), 2);
  const maxE = Math.max(...scores.map((s) => s.mean), 1e-6) * 1.1;
  const x = (s) => left + (W - left - right) * Math.log2(Math.max(s, 1)) / Math.log2(maxS);
  const y = (e) => top + (H - top - bottom) * (1 - e / maxE);
  g.fillText(maxE.toFixed(3), 2, top + 8);
  g.fillText('0', left - 12, H - bottom);
  g.fillText('1', left - 3, H - 6);
  g.fillText(`${maxS} spp`, W - right - 40, H - 6);
  g.fillText('FLIP', 4, H / 2);
  g.strokeStyle = '#7cc4ff';
  g.fillStyle = '#7cc4ff';
  g.beginPath();
  scores.forEach((s, k) => (k === 0 ? g.moveTo(x(s.samples), y(s.mean)) : g.lineTo(x(s.samples), y(s.mean))));
  g.stroke();
  for (const s of scores) g.fillRect(x(s.samples) - 2, y(s.mean) - 2, 4, 4);
}
plot();
