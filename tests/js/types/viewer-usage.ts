// How a documentation page in TypeScript uses the element: compiled (never run) against
// www/clod-viewer.d.ts by tests/js/dts.test.mjs, so a declaration that is wrong or missing
// fails there.
import type { ClodViewerElement, ViewerState } from '../../../www/clod-viewer.js';

const viewer: ClodViewerElement | null = document.querySelector('clod-viewer');
if (viewer) {
  viewer.addEventListener('progress', (e) => console.log(e.detail.phase, e.detail.fraction.toFixed(2)));
  viewer.addEventListener('lod', (e) => {
    const s: ViewerState = e.detail;
    const coarsest = s.levels[s.levels.length - 1];
    console.log(s.lodFrom, coarsest.triangles, coarsest.error, s.levelsStop ?? 'all levels reached');
  });
  viewer.addEventListener('error', (e) => console.error(e.detail.message));
  viewer.addEventListener('meter', (e) => console.log(e.detail.geomorph?.silhouette));
  viewer.setState({ methods: ['popping', 'geomorph'], variant: 'dither', tolerance: 4, pan: [0.1, 0], continuousTriangles: null });
  viewer.pause();
  viewer.setTime(1.2);
  const state = viewer.state();
  const first = state.views[0];
  console.log(first.method, first.level, first.to, first.t, state.meter.popping?.shading, state.crowd?.perLevel.length);
  void viewer.measurePopSpike({ frames: 48 }).then((spike) => console.log(spike.geomorph, spike.views[0].series.length));
  void viewer.readPixels().then(({ width, height, data }) => console.log(width * height * 4 === data.length));
  void viewer.screenshot().then((png) => png.size);
  void viewer.load({ name: 'hero.gltf', bytes: new Uint8Array(), resources: new Map([['hero.bin', new Uint8Array()]]) });
  // The reader's settings kept in the page's own URL, and read back.
  const { preset, pairs } = viewer.link();
  history.replaceState(null, '', `?${new URLSearchParams([['settings', preset], ...pairs])}`);
  const ignored: string[] = viewer.applyLink(pairs);
  console.log(ignored.join('; '));
}
// The tag's type comes from HTMLElementTagNameMap.
const created = document.createElement('clod-viewer');
created.play();
