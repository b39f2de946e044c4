// handrig/compat on the main thread: no .wasm file to serve, no asset configuration.
import init, { HandRig } from "handrig/compat";
import { WATCHED, copy, loadInputs, publish, publishError } from "../shared/report";

async function main(): Promise<void> {
  await init(); // the module is inside the JavaScript
  const { avatar, clip } = await loadInputs();
  const rig = HandRig.fromVrm(new Uint8Array(avatar));
  const rotations = clip.frames.map((frame) => {
    const result = rig.solve(frame);
    return WATCHED.map((bone) => copy(result.bones[bone]));
  });
  publish("handrig/compat", rotations, { bones: rig.boneNames().length });
}

main().catch((e: unknown) => publishError("handrig/compat", e));
