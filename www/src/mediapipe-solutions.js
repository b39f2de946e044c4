// MediaPipe's legacy JavaScript solutions from npm: `@mediapipe/holistic` (pose, face and both
// hands from one camera frame) and `@mediapipe/hands` (hands only). Unlike tasks-vision, their
// npm packages ship the model files (.tflite, packed assets) next to the wasm runtime, so they
// run with nothing but the files the demo's own server serves from www/node_modules: no model
// URL, no network.
//
// The packages are classic scripts (not ES modules) that define a global class (`Holistic`,
// `Hands`); this module loads the script once and wraps the callback API (`onResults` +
// `send`) into one `await detect(image, timeMs)` per frame.
//
// Input is never mirrored here (`selfieMode: false`): MediaPipe sees the camera image as it is,
// so handrig's `inputMirrored` stays false (see webcam.js).

/** The solutions this module runs: npm package, script, global class. */
export const SOLUTIONS = {
  holistic: { pkg: "@mediapipe/holistic", script: "holistic.js", global: "Holistic" },
  hands: { pkg: "@mediapipe/hands", script: "hands.js", global: "Hands" },
};

/** Where www/node_modules is served, relative to this module. */
const NODE_MODULES = new URL("../node_modules/", import.meta.url);

/** The URL of a solution's package folder (ends with "/"). */
export function solutionBase(kind) {
  const s = SOLUTIONS[kind];
  if (!s) throw new Error(`unknown MediaPipe solution "${kind}" (expected ${Object.keys(SOLUTIONS).join(" or ")})`);
  return new URL(`${s.pkg}/`, NODE_MODULES).href;
}

const scripts = new Map();

/** Loads a classic script once (later calls share the promise). */
function loadScript(url) {
  let p = scripts.get(url);
  if (!p) {
    p = new Promise((resolve, reject) => {
      const el = document.createElement("script");
      el.src = url;
      el.crossOrigin = "anonymous";
      el.onload = () => resolve();
      el.onerror = () => {
        scripts.delete(url);
        reject(new Error(`cannot load ${url} (is www/node_modules installed? run \`npm ci --prefix www\`)`));
      };
      document.head.appendChild(el);
    });
    scripts.set(url, p);
  }
  return p;
}

/**
 * Whether WebGL here is a software rasterizer (SwiftShader, llvmpipe...). MediaPipe's legacy
 * solutions run their models as WebGL shaders by default; on a software GL that is about ten
 * times slower than their CPU (XNNPACK) path: 2 s instead of 0.25 s a frame measured here.
 */
export function softwareWebGL() {
  try {
    const c = document.createElement("canvas");
    const gl = c.getContext("webgl2") || c.getContext("webgl");
    if (!gl) return true;
    const ext = gl.getExtension("WEBGL_debug_renderer_info");
    const renderer = String(gl.getParameter(ext ? ext.UNMASKED_RENDERER_WEBGL : gl.RENDERER));
    gl.getExtension("WEBGL_lose_context")?.loseContext();
    return /swiftshader|llvmpipe|softpipe|software|basic render/i.test(renderer);
  } catch {
    return true;
  }
}

/**
 * One legacy solution instance. `await LegacySolution.create("holistic" | "hands", options)`,
 * then `await detect(image, timeMs)` per frame, `close()` at the end.
 *
 * Options: `cpu` (true: CPU inference; default: CPU when WebGL is software), `modelComplexity`
 * (default 1), `maxNumHands` (hands; default 2), `smoothLandmarks` (holistic; default true),
 * `minDetectionConfidence` / `minTrackingConfidence` (default 0.5): the settings the shared
 * recordings were made with.
 */
export class LegacySolution {
  static async create(kind, options = {}) {
    const base = solutionBase(kind);
    const spec = SOLUTIONS[kind];
    const [, meta] = await Promise.all([
      loadScript(base + spec.script),
      fetch(base + "package.json").then((r) => (r.ok ? r.json() : null), () => null),
    ]);
    const Cls = globalThis[spec.global];
    if (typeof Cls !== "function") throw new Error(`${spec.pkg}: ${spec.script} did not define ${spec.global}`);
    const s = new LegacySolution(kind, new Cls({ locateFile: (file) => base + file }));
    s.version = meta?.version ?? "unknown";
    s.cpu = options.cpu ?? softwareWebGL();
    const common = {
      selfieMode: false,
      useCpuInference: s.cpu,
      modelComplexity: options.modelComplexity ?? 1,
      minDetectionConfidence: options.minDetectionConfidence ?? 0.5,
      minTrackingConfidence: options.minTrackingConfidence ?? 0.5,
    };
    s.options =
      kind === "hands"
        ? { ...common, maxNumHands: options.maxNumHands ?? 2 }
        : { ...common, smoothLandmarks: options.smoothLandmarks ?? true, refineFaceLandmarks: false, enableSegmentation: false };
    s.mp.setOptions(s.options);
    await s.mp.initialize();
    return s;
  }

  constructor(kind, mp) {
    this.kind = kind;
    this.mp = mp;
    this.last = null;
    this.closed = false;
    this.inputs = { image: null };
    mp.onResults((r) => {
      this.last = r;
    });
    // The public `send(inputs)` stamps frames with performance.now(). The solution object it
    // wraps (the one own property with `send` and `onResults`) also takes a timestamp, which
    // the recording tool needs: landmark smoothing works in time, and a recording's frames
    // are 1/fps apart whatever the processing took. Found by shape, not by minified name.
    this.inner = Object.values(mp).find(
      (v) => v && v !== mp && typeof v === "object" && typeof v.send === "function" && typeof v.onResults === "function",
    );
  }

  /** Package name and version, e.g. "@mediapipe/holistic 0.5.1675471629". */
  get label() {
    return `${SOLUTIONS[this.kind].pkg} ${this.version}`;
  }

  /**
   * Runs the solution on one image (video, image or canvas). `timeMs`: the frame's timestamp
   * (must increase from call to call; default: now). Resolves to MediaPipe's results object
   * (valid until the next call).
   */
  async detect(image, timeMs) {
    if (this.closed) throw new Error(`${this.label}: detect() after close()`);
    this.last = null;
    this.inputs.image = image;
    if (timeMs !== undefined && this.inner) await this.inner.send(this.inputs, timeMs);
    else await this.mp.send(this.inputs);
    this.inputs.image = null;
    if (!this.last) throw new Error(`${this.label}: no results for the frame`);
    return this.last;
  }

  /** Restarts tracking (the next frame is treated as the first). */
  reset() {
    this.mp.reset();
  }

  close() {
    if (this.closed) return;
    this.closed = true;
    this.mp.close();
  }
}

/**
 * Holistic's pose world landmarks (meters, origin between the hips). The 0.5 build exports
 * them under a minified name (`za`) instead of `poseWorldLandmarks`; both are read.
 */
export function holisticPoseWorld(results) {
  return results.poseWorldLandmarks ?? results.za ?? null;
}
