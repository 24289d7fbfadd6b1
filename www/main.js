// Bootstrap and DOM wiring only: loading, parsing and statistics live in the Rust core.
import init, { Character } from './pkg/clod_viewer.js';

const html = document.documentElement;
const status = document.getElementById('status');
const alert = document.getElementById('error');
const table = document.getElementById('stats');

function showError(message) {
  alert.textContent = message;
  alert.hidden = false;
}

function showStats(name, character) {
  const clips = character.clipNames.map((n) => `${n} (${character.clipDuration(n).toFixed(2)} s)`);
  const rows = [
    ['triangles', character.triangleCount.toLocaleString()],
    ['vertices', character.vertexCount.toLocaleString()],
    ['joints', character.jointCount],
    ['primitives', character.primitiveCount],
    ['clips', clips.join(', ') || 'none'],
    ['warnings', character.warnings.join('; ') || 'none'],
  ];
  document.getElementById('model-name').textContent = name;
  table.tBodies[0].replaceChildren(...rows.map(([k, v]) => {
    const tr = document.createElement('tr');
    const th = document.createElement('th');
    const td = document.createElement('td');
    th.textContent = k;
    td.textContent = v;
    tr.append(th, td);
    return tr;
  }));
  table.hidden = false;
}

async function load(name, bytes) {
  alert.hidden = true;
  try {
    const character = Character.fromGlb(bytes);
    showStats(name, character);
    character.free();
    status.textContent = `Loaded ${name}.`;
  } catch (e) {
    // The previous statistics stay on screen: a bad file never blanks the page.
    showError(`Could not load ${name}: ${e.message}`);
  }
}

try {
  await init();
  status.textContent = 'Ready: open a .glb file.';
  html.dataset.state = 'ready';
} catch (e) {
  html.dataset.state = 'error';
  showError(`The WebAssembly core failed to start: ${e.message}`);
}

document.getElementById('file').addEventListener('change', async (event) => {
  const file = event.target.files[0];
  if (file) await load(file.name, new Uint8Array(await file.arrayBuffer()));
});
