// Types of the `<clod-viewer>` element (clod-viewer.js) for documentation pages written in
// TypeScript, or for an editor's completion in plain JavaScript:
//
//   import type { ClodViewerElement, ViewerState } from './viewer/clod-viewer.js';
//   const viewer = document.querySelector('clod-viewer')!; // typed: HTMLElementTagNameMap below
//
// The viewer's shapes are Rust types (src/js_api/viewer_state.rs, viewer_settings.rs);
// tests/js/dts.test.mjs checks this file against a fully populated serialization of them
// (tests/js/types/api-samples.json) with the TypeScript compiler, and fails when `state()`,
// `setState`, `meterHistory()`, `measurePopSpike`, `replay()`, `flipImages` or the element gain,
// lose or change a name.

/** A transition method: what each view shows. */
export type Method = 'popping' | 'alpha' | 'geomorph';

/** One view of the canvas: the transition it draws this frame. */
export interface ViewState {
  method: Method;
  /** The level shown, and the level the running transition goes to (equal when none runs). With
   * the continuous slider on, `levels.length` and `levels.length + 1` are its finer and coarser
   * states (the labels then say "continuous"). */
  level: number;
  to: number;
  /** The transition's progress, 0..1. */
  t: number;
  /** Triangles drawn in this view (crowd: over every instance). */
  triangles: number;
  /** Draw calls of the view. */
  draws: number;
  /** `[x, y, width, height]` in canvas pixels. */
  rect: [number, number, number, number];
}

/**
 * The live meter's pop for one method through the last transition: its largest *step*, the
 * difference between a frame and its control (the same frame drawn with the view's plan of the
 * previous measured frame), so what the transition itself changed; 0 for a view whose plan held.
 */
export interface MethodPop {
  /** % of the view's pixels whose coverage the step changed. */
  silhouette: number;
  /** Mean |ΔRGB| per pixel both cover, 0..765. */
  shading: number;
  transitions: number;
  /** Without the control: the largest frame-to-frame change of the difference from the
   * full-detail reference (the meter's former pop; includes the animation's own change). */
  uncontrolled: { silhouette: number; shading: number };
}

/** `meterHistory()`: the live meter's recent samples (about ten seconds), oldest first. */
export interface MeterHistory {
  /** The method of each view. */
  methods: Method[];
  /** `[seconds, transitionRunning, silhouette %, shading, … per view]`: each view's difference from the reference. */
  samples: (number | boolean)[][];
  /** `[silhouette %, shading, … per view]`: each view's step (against its control) in the same frames. */
  steps: number[][];
  /** `[FLIP against full detail, FLIP of the step, … per view]` in the same frames, 0..1. */
  flip: number[][];
}

/** `replay()`: every view's meter pictures across the last transition, cropped to the region of
 * its largest change, and each view's per-frame curves from the frame before it to the frame after. */
export interface Replay {
  methods: Method[];
  /** `[from, to]` levels. */
  levels: [number, number];
  /** The meter picture's `[width, height]`, pixels. */
  size: [number, number];
  /** The crop, `[x, y, width, height]` in meter pixels. */
  region: [number, number, number, number];
  /** The frame before the transition, evenly spread frames of it and the frame after; each view's crop as RGBA8. */
  frames: { frame: number; time: number; t: number; views: Uint8Array[] }[];
  /** Per measured frame; the per-view arrays hold one value per frame. Silhouette in % of the
   * view, shading in mean |ΔRGB|, FLIP 0..1; `step…` against the view's control. */
  curves: {
    frame: number[];
    time: number[];
    running: boolean[];
    silhouette: number[][];
    shading: number[][];
    flip: number[][];
    stepSilhouette: number[][];
    stepFlip: number[][];
  };
}

/** LDR-FLIP in the live meter (`state().meter.flip`): null where the GPU cannot compute it, with
 * FLIP off, before a frame was compared, and in crowd mode (the crowd meter compares silhouettes
 * and shading). */
export interface MeterFlip {
  /** Pixels per degree of the meter's picture when the view is seen at FLIP's standard 67. */
  ppd: number;
  /** Each view's mean FLIP error against full detail in the last measured frame, 0..1. */
  views: number[];
  /** The last transition's FLIP pop per method (largest mean error of a frame against its control). */
  pop: { popping: number | null; alpha: number | null; geomorph: number | null };
  /** The same without the control: the largest frame-to-frame change of the error against full detail. */
  uncontrolled: { popping: number | null; alpha: number | null; geomorph: number | null };
}

/** A setting the two presets differ in: its `setState` key, current value and both presets' values. */
export interface PresetValue {
  key: 'tolerance' | 'magnify' | 'transitionSpeed' | 'dollyPeriod';
  label: string;
  value: number;
  demonstration: number;
  realistic: number;
}

/** `state().preset`: the preset the settings match (null once a control moved), and what it sets. */
export interface PresetState {
  name: 'demonstration' | 'realistic' | null;
  /** The LOD threshold in pixels of this view (the demonstration's is per 400 px of view height). */
  tolerancePx: number;
  values: PresetValue[];
}

/** Per view, how its difference from full detail changes over the meter's history. */
export interface MeterChange {
  silhouetteMean: number;
  silhouettePeak: number;
  silhouettePerSecond: number;
  shadingMean: number;
  shadingPeak: number;
  shadingPerSecond: number;
}

export interface MeterState {
  on: boolean;
  /** FLIP is measured (`setState({ flip })`). */
  flipOn: boolean;
  /** The meter's picture size per view, `[width, height]` pixels. */
  size: [number, number];
  transitions: number;
  samples: number;
  /** Frames with no free readback (the next change then counts over two frames). */
  gaps: number;
  popping: MethodPop | null;
  alpha: MethodPop | null;
  geomorph: MethodPop | null;
  changes: MeterChange[];
  /** Null where the GPU cannot compute FLIP, FLIP is off, or before a frame needed it. */
  flip: MeterFlip | null;
}

/** What the crowd shows this frame (`mode: 'crowd'`). */
export interface CrowdState {
  instances: number;
  drawn: number;
  /** Instances drawn at each level. */
  perLevel: number[];
  transitions: number;
  trianglesDrawn: number;
  trianglesFull: number;
  viewTriangles: number[];
  paletteRows: number;
}

/** `viewer.state()`: what the views show, with the settings in force. */
export interface ViewerState {
  backend: 'webgpu' | 'webgl2';
  adapter: string;
  format: string;
  msaa: number;
  composed: boolean;
  width: number;
  height: number;
  /** Triangles of the full mesh. */
  triangles: number;
  joints: number;
  clips: string[];
  clipDurations: number[];
  /** Index into `clips`, or null for the rest pose. */
  clip: number | null;
  /** Finest first; one entry (the full mesh) until the levels arrive. `error` in model units. */
  levels: { triangles: number; error: number }[];
  /** Each level's switch distance, × the framing distance. */
  switch: number[];
  /** Where and why the levels stop short of the coarsest count asked for (a sentence), or null. */
  levelsStop: string | null;
  buildMs: number;
  builtOffMainThread: boolean;
  /** Null until the levels are attached; then where they came from. */
  lodFrom: 'build' | 'cache' | 'inline' | null;
  /** The level the camera distance selects. */
  selected: number;
  /** × the framing distance. */
  distance: number;
  /** The cameras' vertical field of view, radians. */
  fovy: number;
  animTime: number;
  paused: boolean;
  speed: number;
  /** Degrees. */
  yaw: number;
  pitch: number;
  pan: [number, number];
  distanceMode: 'dolly' | 'manual';
  overlay: 'none' | 'wireframe' | 'levels' | 'skeleton' | 'difference';
  transition: 'time' | 'distance';
  duration: number;
  zone: number;
  /** The alpha-blending view's variant. */
  variant: 'opaque-first' | 'naive' | 'dither';
  transitionSpeed: number;
  magnify: number;
  meter: MeterState;
  /** The continuous slider's triangle count, or null when off. */
  continuousTriangles: number | null;
  /** The slider's range: the full mesh's triangles once the levels are there, else 0. */
  maxTriangles: number;
  stacked: boolean;
  views: ViewState[];
  frames: number;
  morphTargets: number;
  morphs: boolean;
  mode: 'single' | 'crowd';
  crowd: CrowdState | null;
  preset: PresetState;
  errors: string[];
  warnings: string[];
}

/** `viewer.setState(settings)`: any subset; an unknown key or a bad value throws, and nothing changes. */
export interface ViewerSettings {
  paused?: boolean;
  /** Animation seconds. */
  time?: number;
  speed?: number;
  /** A clip name; null for the rest pose. */
  clip?: string | null;
  distanceMode?: 'dolly' | 'manual';
  /** × the framing distance (switches to manual). */
  distance?: number;
  dollyPeriod?: number;
  /** Degrees; pitch is clamped to ±85. */
  yaw?: number;
  pitch?: number;
  /** `[x, y]` in framing distances, each in [-100, 100]. */
  pan?: [number, number];
  resetCamera?: boolean;
  /** Pixels of screen error at which a level switches. */
  tolerance?: number;
  hysteresis?: number;
  transition?: 'time' | 'distance';
  /** Seconds per level. */
  duration?: number;
  zone?: number;
  /** 0.01..1: slow motion of the transitions alone. */
  transitionSpeed?: number;
  /** 1..16. */
  magnify?: number;
  meter?: boolean;
  /** The meter also measures LDR-FLIP (on by default; on a software rasterizer most of a measured
   * frame's time). */
  flip?: boolean;
  variant?: 'naive' | 'opaque-first' | 'dither';
  /** One to three methods: the views, in order. */
  methods?: Method[];
  /** A triangle count through the progressive mesh, or null for off. */
  continuousTriangles?: number | null;
  overlay?: 'none' | 'wireframe' | 'levels' | 'skeleton' | 'difference';
  mode?: 'single' | 'crowd';
  /** False: the crowd at full detail. */
  crowdLod?: boolean;
  /** False: the base shape, morph weights ignored. */
  morphs?: boolean;
  /** Crowd instances, 1..4096. */
  count?: number;
  /** The demonstration's exaggerated settings or the realistic defaults (applied before the call's other keys). */
  preset?: 'demonstration' | 'realistic';
}

/** `measurePopSpike(options)`: every key optional; an unknown key or a bad value rejects. */
export interface PopSpikeOptions {
  /** The switch to this level from the one before (default: the coarsest). */
  level?: number;
  /** Offscreen frames drawn, 8..600 (default 96). */
  frames?: number;
  /** Fraction of the distance moved, 1e-4..0.5 (default 0.008). */
  sweep?: number;
  /** Framing distances where the switch is placed, 0.5..50 (default 1). */
  at?: number;
}

/** `measurePopSpike(options)`'s result: each method's largest frame-to-frame mean |ΔRGB| per pixel
 * (0..765) through one LOD switch, null for a method no view shows. */
export interface PopSpike {
  popping: number | null;
  alpha: number | null;
  geomorph: number | null;
  variant: 'naive' | 'opaque-first' | 'dither';
  level: number;
  frames: number;
  /** Where the switch was placed, × the framing distance, and the distance swept (fraction). */
  at: number;
  sweep: number;
  /** Seconds the measurement took. */
  duration: number;
  /** Per view: its method, its largest change and the change at every frame. */
  views: { method: Method; largest: number; series: number[] }[];
}

/** `flipImages()`'s result: LDR-FLIP's error map of two pictures, 0..1. */
export interface FlipResult {
  mean: number;
  /** The 99th percentile. */
  p99: number;
  max: number;
  /** The pixels per degree the pictures were seen at. */
  ppd: number;
}

/** A model to show: a `.glb`, or a `.gltf` with its buffers and images by file name. */
export interface ModelSource {
  name: string;
  bytes: Uint8Array;
  resources?: Map<string, Uint8Array>;
}

/**
 * What an `error` event is about: `fetch` (the model could not be downloaded), `model` (the file
 * cannot be shown), `levels` (the LOD levels could not be built; the full mesh keeps playing),
 * `no-gpu` (neither WebGPU nor WebGL2), `wasm` (the viewer's own files did not load), `attribute`
 * (an attribute value the viewer does not take), `render` (the GPU reported an error while drawing).
 */
export type ErrorCode = 'fetch' | 'model' | 'levels' | 'no-gpu' | 'wasm' | 'attribute' | 'render';

/** The element's own events (it fires the usual DOM events too). */
export interface ClodViewerEventMap {
  progress: CustomEvent<{ phase: 'fetch' | 'gpu' | 'build' | 'ready'; fraction: number }>;
  /** The full mesh is drawn from now on. */
  load: CustomEvent<LoadedState>;
  /** The levels are attached (`lodFrom` 'build', 'cache' or 'inline'). */
  lod: CustomEvent<ViewerState>;
  /** A real failure, once each: `code` says which kind (see `ErrorCode`), `message` what happened. */
  error: CustomEvent<{ code: ErrorCode; message: string }>;
  /** The live meter measured a transition. */
  meter: CustomEvent<{ popping: MethodPop | null; alpha: MethodPop | null; geomorph: MethodPop | null }>;
  /** A drag, wheel, touch or key moved the camera (`state()` has it). */
  camerachange: CustomEvent<undefined>;
}

/** The state `load` fires and `load()` resolves with: the viewer's state and the file's name. */
export interface LoadedState extends ViewerState {
  name: string;
}

/** `<clod-viewer src clip modes variant tolerance backend autoplay loading mode count preset manual-frames>`. */
export class ClodViewerElement extends HTMLElement {
  static observedAttributes: string[];
  /** The canvas the views are drawn on. */
  readonly canvas: HTMLCanvasElement | null;
  /** `webgpu` or `webgl2` once loaded. */
  readonly backend: 'webgpu' | 'webgl2' | null;
  /** Mean time between drawn frames, ms (0 before two frames). */
  readonly frameMs: number;
  /** Attribute values the model shown cannot take, each with the reason: they were ignored. */
  readonly ignoredSettings: string[];
  play(): void;
  pause(): void;
  setTime(seconds: number): void;
  setState(settings: ViewerSettings): void;
  state(): ViewerState;
  /** The settings as a link carries them: the preset it names and the `[key, value]` pairs
   * (`setState`'s keys, values as text) that differ from it. */
  link(): { preset: 'demonstration' | 'realistic'; pairs: [string, string][] };
  /** Applies a link's `[key, value]` pairs, each on its own, after its preset; keys that are
   * not a link's are left alone. Returns a message for each pair whose value was not taken. */
  applyLink(pairs: [string, string][]): string[];
  meter(): { popping: MethodPop | null; alpha: MethodPop | null; geomorph: MethodPop | null };
  meterHistory(): MeterHistory;
  /** The last transition's replay, or null before one completed. */
  replay(): Replay | null;
  /** The replay drawn as one PNG (see `drawReplay`), or null before a transition. */
  replayPng(): Promise<Blob | null>;
  /** Rejects with `superseded: true` (as `readPixels`, `screenshot`, `textureLevels`,
   * `flipImages` and `finish` do) when another model replaces the one shown before it finishes. */
  measurePopSpike(options?: PopSpikeOptions): Promise<PopSpike>;
  /** Draws one frame at `nowMs` (with `manual-frames`) and returns the state. */
  renderFrame(nowMs: number): ViewerState;
  /** The current frame: RGBA8, top row first. */
  readPixels(): Promise<{ width: number; height: number; data: Uint8Array }>;
  /** Mip levels of material `i`'s base-colour texture, means in linear light. */
  textureLevels(i: number): Promise<{ width: number; height: number; mean: [number, number, number, number] }[]>;
  /** Resolves when the GPU has finished the submitted frames. */
  finish(): Promise<void>;
  /** LDR-FLIP (Andersson et al. 2020) of two RGBA8 sRGB pictures on the viewer's GPU, seen at
   * `ppd` pixels per degree (default 67.02): the error map's mean, 99th percentile and maximum,
   * or null where the GPU cannot render into float targets. */
  flipImages(reference: Uint8Array, test: Uint8Array, width: number, height: number, ppd?: number): Promise<FlipResult | null>;
  /** A PNG of the current frame with the views' labels. */
  screenshot(): Promise<Blob>;
  /** Shows another model, keeping the comparison settings (threshold, hysteresis, transitions,
   * methods, variant, speed, distance and dolly period, magnifier, overlay, meter, FLIP, crowd,
   * morphs; not the clip, whether it plays, or the orbit); on failure the previous one keeps
   * playing. */
  load(source: ModelSource): Promise<LoadedState>;
  addEventListener<K extends keyof ClodViewerEventMap>(
    type: K,
    listener: (this: ClodViewerElement, event: ClodViewerEventMap[K]) => unknown,
    options?: boolean | AddEventListenerOptions,
  ): void;
  addEventListener(type: string, listener: EventListenerOrEventListenerObject, options?: boolean | AddEventListenerOptions): void;
}

/** Each `error` event's `code`, with what it means to a page. */
export const ERROR_CODES: Record<ErrorCode, string>;
/** Loads (once per page) the wasm build of a backend. */
export function loadBuild(backend: 'webgpu' | 'webgl2'): Promise<{ module: unknown; url: string }>;
/** Loads (once per page) the Draco decoder module, which only files with Draco-compressed geometry need. */
export function loadDraco(): Promise<{ decode: (stream: Uint8Array, request: Uint32Array) => Uint8Array }>;
/** Whether this browser hands out a WebGPU adapter. */
export function webgpuWorks(): Promise<boolean>;
/** A `.gltf` resolver over dropped files, by name (the wasm side asks for a URI's path, then its last segment). */
export function resolverFor(resources: Map<string, Uint8Array> | undefined): (name: string) => Uint8Array | null;
/** Colours of the methods in the page's charts and the replay. */
export const METHOD_COLORS: Record<Method, string>;
/** Draws `replay` on `canvas` (resized to fit): a row per view, its crops magnified `zoom` times
 * (default 2) and its per-frame difference curves under them. */
export function drawReplay(canvas: HTMLCanvasElement, replay: Replay, options?: { zoom?: number }): void;

declare global {
  interface HTMLElementTagNameMap {
    'clod-viewer': ClodViewerElement;
  }
}
