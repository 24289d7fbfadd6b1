// The replay of a transition drawn on a canvas, for <clod-viewer>'s `replayPng()` and the viewer
// page's film strip (clod-viewer.js re-exports both names). Drawing only: which frames, which
// region and the curves come from the Rust viewer (`viewer.replay()`, src/render/replay.rs).

// Colours of the methods in charts and replays.
export const METHOD_COLORS = { popping: '#ff7a5c', alpha: '#f5d547', geomorph: '#5cd0ff' };

/**
 * Draws `replay` (`element.replay()`) on `canvas`, resized to fit: one row per view with its
 * method, the frames' crops magnified `zoom` times (the transition's `t` under each), and under
 * it the view's per-frame difference from full detail (silhouette % solid, FLIP × 100 dashed),
 * with a tick at each frame shown.
 */
export function drawReplay(canvas, replay, { zoom = 2 } = {}) {
  const [, , w, h] = replay.region;
  const label = 96;
  const cell = w * zoom + 4;
  const curve = 56;
  const row = h * zoom + 16 + curve + 10;
  canvas.width = label + cell * replay.frames.length + 8;
  canvas.height = 22 + row * replay.methods.length;
  const ctx = canvas.getContext('2d');
  ctx.fillStyle = '#1d2430';
  ctx.fillRect(0, 0, canvas.width, canvas.height);
  ctx.fillStyle = '#fff';
  ctx.font = '12px system-ui, sans-serif';
  const [from, to] = replay.levels;
  const span = replay.curves.frame;
  ctx.fillText(`Level ${from} → ${to}: frames ${span[0]}–${span.at(-1)}, the region of the largest change (${w} × ${h} meter pixels) magnified ×${zoom}; curves: difference from full detail`, 6, 15);
  const tile = document.createElement('canvas');
  tile.width = w;
  tile.height = h;
  const tileCtx = tile.getContext('2d');
  ctx.imageSmoothingEnabled = false;
  const top = Math.max(0.01, ...replay.curves.silhouette.flat(), ...replay.curves.flip.flat().map((f) => 100 * f));
  const x = (k) => label + (cell * replay.frames.length - 4) * (span.length > 1 ? k / (span.length - 1) : 0.5);
  replay.methods.forEach((method, v) => {
    const y0 = 22 + row * v;
    ctx.fillStyle = METHOD_COLORS[method] ?? '#fff';
    ctx.fillText(method, 6, y0 + 14);
    replay.frames.forEach((f, i) => {
      tileCtx.putImageData(new ImageData(new Uint8ClampedArray(f.views[v]), w, h), 0, 0);
      ctx.fillStyle = '#8a96a6';
      ctx.fillRect(label + cell * i, y0, w * zoom, h * zoom);
      ctx.drawImage(tile, label + cell * i, y0, w * zoom, h * zoom);
      ctx.fillStyle = '#ccc';
      ctx.fillText(f.t.toFixed(2), label + cell * i, y0 + h * zoom + 12);
    });
    const base = y0 + h * zoom + 16 + curve;
    ctx.strokeStyle = 'rgb(255 255 255 / 0.3)';
    ctx.strokeRect(label, base - curve, cell * replay.frames.length - 4, curve);
    for (const f of replay.frames) {
      const k = span.indexOf(f.frame);
      if (k >= 0) { ctx.beginPath(); ctx.moveTo(x(k), base - curve); ctx.lineTo(x(k), base); ctx.stroke(); }
    }
    const line = (values, dash) => {
      ctx.setLineDash(dash);
      ctx.strokeStyle = METHOD_COLORS[method] ?? '#fff';
      ctx.beginPath();
      values.forEach((value, k) => (k ? ctx.lineTo : ctx.moveTo).call(ctx, x(k), base - (value / top) * (curve - 4)));
      ctx.stroke();
      ctx.setLineDash([]);
    };
    line(replay.curves.silhouette[v], []);
    line(replay.curves.flip[v].map((f) => 100 * f), [4, 3]);
    ctx.fillStyle = '#ccc';
    ctx.fillText(`silhouette % (solid), FLIP × 100 (dashed), 0–${top.toFixed(2)}`, 6, base - 4);
  });
}
