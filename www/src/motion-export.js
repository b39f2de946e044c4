// The demo's motion export and playback (docs/guide/export.md): a live session's solved frames go
// into handrig's MotionRecorder, saved as .vrma (VRM Animation) or .bvh; a dropped .vrma plays
// on the loaded avatar through @pixiv/three-vrm-animation, so the round trip can be seen.

import * as THREE from "three";
import { GLTFLoader } from "three/addons/loaders/GLTFLoader.js";
import { VRMAnimationLoaderPlugin, VRMLookAtQuaternionProxy, createVRMAnimationClip } from "@pixiv/three-vrm-animation";
import { MotionRecorder } from "handrig";

/** Offers `data` as a download named `name`. */
export function download(data, name, type) {
  const blob = new Blob([data], { type });
  const a = document.createElement("a");
  a.href = URL.createObjectURL(blob);
  a.download = name;
  document.body.appendChild(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(a.href), 10_000);
}

/** Records the "with" view's results during a live recording. */
export class MotionCapture {
  constructor(rig) {
    this.recorder = new MotionRecorder(rig);
    this.rig = rig;
    this.error = null;
  }

  /** Adds a result of `rig` (skipped after an error, or when the rig was re-created). */
  add(timeMs, rig, result) {
    if (this.error || !result) return;
    if (rig !== this.rig) {
      this.error = "the rig was re-created (an option or the avatar changed) during the recording: motion kept up to there";
      return;
    }
    try {
      this.recorder.add(timeMs, result);
    } catch (e) {
      this.error = e.message;
    }
  }
}

/** A parsed .vrma, played on the views' avatars by AnimationMixers. */
export class VrmaPlayer {
  /** Parses the file's bytes (throws when it is not a VRM Animation). */
  static async load(bytes, name) {
    const loader = new GLTFLoader();
    loader.register((parser) => new VRMAnimationLoaderPlugin(parser));
    const gltf = await loader.parseAsync(bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength), "");
    const animation = gltf.userData.vrmAnimations?.[0];
    if (!animation) throw new Error(`${name} has no VRM animation (VRMC_vrm_animation)`);
    return new VrmaPlayer(animation, name);
  }

  constructor(animation, name) {
    this.animation = animation;
    this.name = name;
    this.time = 0;
    this.mixers = [];
    this.actions = [];
  }

  get duration() {
    return this.animation.duration;
  }

  /** (Re)binds the animation to these VRMs (after an avatar change). */
  bind(vrms) {
    for (const m of this.mixers) m.stopAllAction();
    this.actions = [];
    this.mixers = vrms.map((vrm) => {
      if (vrm.lookAt && !vrm.scene.children.some((o) => o instanceof VRMLookAtQuaternionProxy)) {
        const proxy = new VRMLookAtQuaternionProxy(vrm.lookAt);
        proxy.name = "lookAtQuaternionProxy";
        vrm.scene.add(proxy);
      }
      const mixer = new THREE.AnimationMixer(vrm.scene);
      const action = mixer.clipAction(createVRMAnimationClip(this.animation, vrm));
      action.setLoop(THREE.LoopOnce, 1);
      action.clampWhenFinished = true;
      action.play();
      this.actions.push(action);
      return mixer;
    });
    this.seek(this.time);
    return this.mixers.length;
  }

  /** Shows the animation at `t` seconds (clamped to its duration). */
  seek(t) {
    this.time = Math.min(Math.max(0, t), this.duration);
    // A LoopOnce action that reached its end is paused (clampWhenFinished): reset it, so that
    // setTime can take it anywhere again.
    for (const a of this.actions) a.reset();
    for (const m of this.mixers) m.setTime(this.time);
  }

  stop() {
    for (const m of this.mixers) m.stopAllAction();
    this.mixers = [];
    this.actions = [];
  }
}
