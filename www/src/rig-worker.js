// handrig in a Web Worker: tracking and solving off the main thread. The worker owns the rig;
// the page sends MediaPipe frames (structured clone) and gets the flat output back as a
// transferred Float32Array, which `applyToVRM(vrm, output)` applies directly (no object built,
// nothing copied twice). See www/worker.html and docs/guide/workers.md.
//
// Messages in:  { type: "init", wasm: ArrayBuffer, vrm: ArrayBuffer, options? }
//               { type: "solve", frame, output: ArrayBuffer }   (an output buffer to fill, handed
//                                                               back and forth: no allocation)
// Messages out: { type: "ready", bones }   { type: "solved", output, timeMs, us }
//               { type: "error", message }

// Module workers do not see the page's import map: import the package by path (a bundler would
// resolve "handrig" here as usual).
import { HandRig, initSync, LAYOUT } from "../handrig/index.js";

let rig = null;

self.onmessage = (e) => {
  const msg = e.data;
  try {
    if (msg.type === "init") {
      initSync(msg.wasm);
      rig = HandRig.fromVrm(new Uint8Array(msg.vrm), msg.options);
      self.postMessage({ type: "ready", bones: rig.boneNames() });
    } else if (msg.type === "solve") {
      const t0 = performance.now();
      rig.solve(msg.frame); // packs the frame into rig.input and solves into rig.output
      const output = new Float32Array(msg.output, 0, LAYOUT.output.length);
      output.set(rig.output);
      const us = (performance.now() - t0) * 1000;
      self.postMessage({ type: "solved", output: msg.output, timeMs: msg.frame.timeMs, us }, [msg.output]);
    }
  } catch (err) {
    // The buffer goes back too, so the page can keep sending frames.
    const transfer = msg.output instanceof ArrayBuffer && msg.output.byteLength ? [msg.output] : [];
    self.postMessage({ type: "error", message: err.message, output: msg.output }, transfer);
  }
};
