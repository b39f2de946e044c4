// The idiomatic JS layer over the raw wasm-bindgen `HandRig` (rapier.js style: the wasm class
// stays thin, users get this one). Shared by every entry point: build.mjs wraps this file as
// an ES module (browsers, bundlers) or CommonJS (Node), so it has no imports or exports itself.
//
// What it adds over the raw class, and why:
// - a clear "call init() first" error instead of wasm-bindgen's `undefined` dereference when a
//   browser build is used before its WebAssembly is instantiated;
// - every failure is an `Error` instance (wasm-bindgen throws whatever the Rust side gave);
// - `fromVrm` takes a Uint8Array, Node Buffer, ArrayBuffer or any typed array / DataView;
// - `free()` is idempotent, a freed rig says so by name, and `using rig = ...` frees it;
// - methods the raw class gains later are forwarded unchanged (see `forwardRawMembers`), so a
//   new wasm method works before this file learns about it (the d.ts test lists gaps).
// Per-frame cost is one extra JS call and a try/catch around `solve`: nothing is allocated.

/* exported createHandRigApi */
// eslint-disable-next-line no-unused-vars
function createHandRigApi(raw, isReady) {
  "use strict";
  const RawHandRig = raw.HandRig;
  // Constructor token for wrapping a raw rig made by a static factory (fromVrm).
  const ADOPT = {};
  // wrapper -> raw rig; `null` once freed.
  const rawOf = new WeakMap();

  function ensureReady(what) {
    if (!isReady()) {
      throw new Error(
        `handrig: ${what} was called before the WebAssembly module was initialized. ` +
          "In browsers and bundlers, `await init()` (the package's default export) first.",
      );
    }
  }

  function asError(e) {
    if (e instanceof Error) return e;
    // Errors from another realm (iframe, vm context) are still errors: keep them.
    if (e !== null && typeof e === "object" && typeof e.message === "string") return e;
    return new Error(typeof e === "string" ? e : `handrig: ${String(e)}`);
  }

  function liveRaw(rig, method) {
    const r = rawOf.get(rig);
    if (r === undefined) {
      throw new TypeError(`HandRig.prototype.${method} called on an object that is not a HandRig`);
    }
    if (r === null) {
      throw new Error(`HandRig.${method}: this rig was freed (free() was called); create a new HandRig`);
    }
    return r;
  }

  function tag(bytes) {
    return Object.prototype.toString.call(bytes);
  }

  // Accepts what file/fetch/fs APIs hand out; checks by tag so other realms' buffers work.
  function vrmBytes(bytes) {
    if (bytes instanceof Uint8Array) return bytes;
    const t = tag(bytes);
    if (t === "[object ArrayBuffer]" || t === "[object SharedArrayBuffer]") {
      return new Uint8Array(bytes);
    }
    if (ArrayBuffer.isView(bytes)) {
      return new Uint8Array(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    }
    throw new TypeError(
      "bytes: must be the .vrm file's contents as a Uint8Array, ArrayBuffer, Buffer or typed array" +
        (bytes === undefined ? " (got undefined)" : ` (got ${t.slice(8, -1)})`),
    );
  }

  class HandRig {
    /**
     * `new HandRig(restPose, options?)`: a solver for one avatar. `restPose.bones` maps VRM 1.0
     * humanoid bone names to rest world positions [x, y, z] (meters, the model's own frame,
     * three-vrm's normalized bones); `restPose.vrmVersion` is "0" or "1" (default "1").
     */
    constructor(restPose, options) {
      if (restPose === ADOPT) {
        rawOf.set(this, options);
        return;
      }
      ensureReady("new HandRig()");
      let r;
      try {
        r = new RawHandRig(restPose, options);
      } catch (e) {
        throw asError(e);
      }
      rawOf.set(this, r);
    }

    /** A rig for a `.vrm` file (VRM 1.0 or 0.x), read directly from its bytes. */
    static fromVrm(bytes, options) {
      ensureReady("HandRig.fromVrm()");
      const u8 = vrmBytes(bytes);
      let r;
      try {
        r = RawHandRig.fromVrm(u8, options);
      } catch (e) {
        throw asError(e);
      }
      return new HandRig(ADOPT, r);
    }

    /** Every option: `{ path, type, default, values?, min?, max?, step?, description }`. */
    static optionDescriptions() {
      ensureReady("HandRig.optionDescriptions()");
      try {
        return RawHandRig.optionDescriptions();
      } catch (e) {
        throw asError(e);
      }
    }

    /** Solves one frame; see the README for the frame and result shapes. */
    solve(frame) {
      const r = liveRaw(this, "solve");
      try {
        return r.solve(frame);
      } catch (e) {
        throw asError(e);
      }
    }

    /** `{ [boneName]: [x, y, z] }`: rest world positions, meters, the model's own frame. */
    restWorldPositions() {
      return liveRaw(this, "restWorldPositions").restWorldPositions();
    }

    /** The bones this avatar has, parent-first, VRM 1.0 names. */
    boneNames() {
      return liveRaw(this, "boneNames").boneNames();
    }

    /** Releases the wasm memory. Safe to call twice; the rig is unusable afterwards. */
    free() {
      const r = rawOf.get(this);
      if (r) {
        rawOf.set(this, null);
        r.free();
      }
    }

    /** True once `free()` was called. */
    get freed() {
      return rawOf.get(this) === null;
    }
  }

  if (typeof Symbol === "function" && typeof Symbol.dispose === "symbol") {
    Object.defineProperty(HandRig.prototype, Symbol.dispose, {
      value: HandRig.prototype.free,
      writable: true,
      configurable: true,
    });
  }

  // Members of the raw class this file does not wrap explicitly (getters such as vrmVersion,
  // methods such as resetCalibration, and whatever the bindings gain later) are forwarded.
  // wasm-bindgen internals (`__wbg_*`, `__destroy_into_raw`, `__wrap`) are not.
  function forwardRawMembers() {
    const internal = (name) =>
      typeof name !== "string" || name === "constructor" || name.startsWith("__");
    for (const name of Object.getOwnPropertyNames(RawHandRig.prototype)) {
      if (internal(name) || Object.prototype.hasOwnProperty.call(HandRig.prototype, name)) {
        continue;
      }
      const d = Object.getOwnPropertyDescriptor(RawHandRig.prototype, name);
      const forwarded = { configurable: true, enumerable: false };
      if (typeof d.value === "function") {
        forwarded.writable = true;
        forwarded.value = {
          [name](...args) {
            const r = liveRaw(this, name);
            try {
              return r[name](...args);
            } catch (e) {
              throw asError(e);
            }
          },
        }[name];
      } else {
        if (d.get) {
          forwarded.get = function () {
            return liveRaw(this, name)[name];
          };
        }
        if (d.set) {
          forwarded.set = function (v) {
            const r = liveRaw(this, name);
            try {
              r[name] = v;
            } catch (e) {
              throw asError(e);
            }
          };
        }
      }
      Object.defineProperty(HandRig.prototype, name, forwarded);
    }
    for (const name of Object.getOwnPropertyNames(RawHandRig)) {
      if (internal(name) || Object.prototype.hasOwnProperty.call(HandRig, name)) continue;
      const d = Object.getOwnPropertyDescriptor(RawHandRig, name);
      if (typeof d.value !== "function") continue;
      Object.defineProperty(HandRig, name, {
        configurable: true,
        writable: true,
        value: {
          [name](...args) {
            ensureReady(`HandRig.${name}()`);
            try {
              return RawHandRig[name](...args);
            } catch (e) {
              throw asError(e);
            }
          },
        }[name],
      });
    }
  }
  forwardRawMembers();

  return { HandRig };
}
