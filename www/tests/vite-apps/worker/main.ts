// handrig/worker: the rig solves in a module Worker; results come back as transferred
// Float32Arrays (the flat output), read here with readRotation.
import { createRigWorker, readRotation } from "handrig/worker";
import { WATCHED, copy, loadInputs, publish, publishError } from "../shared/report";

async function main(): Promise<void> {
  const { avatar, clip } = await loadInputs();
  const worker = new Worker(new URL("./rig.worker.ts", import.meta.url), { type: "module" });
  const rig = await createRigWorker(worker, { avatar });
  const q: number[] = [0, 0, 0, 1];
  let rotations: (number[] | null)[][] = [];
  const times: number[] = [];
  rig.onResult = ({ output, timeMs }) => {
    times.push(timeMs);
    rotations.push(WATCHED.map((bone) => copy(readRotation(output, bone, q))));
  };
  const errors: string[] = [];
  rig.onError = (m) => errors.push(m);
  // Every frame, one at a time (as a camera slower than the worker would give them).
  for (const frame of clip.frames) {
    rig.solve(frame);
    await rig.idle();
  }
  const paced = { ...rig.stats };
  const solved = rotations;
  // A burst: every frame at once, as a camera faster than the worker. The first is sent, the
  // newest waits, the rest are dropped.
  rotations = [];
  times.length = 0;
  for (const frame of clip.frames) rig.solve(frame);
  await rig.idle();
  const burst = { stats: { ...rig.stats }, times: [...times] };
  // A bad frame: an error, and the rig still solves after it. (TypeScript catches it too, as it
  // does on the page: RigWorker.solve takes a FrameInput.)
  // @ts-expect-error -- a wrong frame on purpose
  rig.solve({ timeMs: 1e9, hands: "nope" });
  await rig.idle();
  rig.solve(clip.frames[clip.frames.length - 1]!);
  await rig.idle();
  const after = { errors: [...errors], solvedAfter: rig.stats.solved, lastTime: times[times.length - 1] };
  publish("handrig/worker", solved, { paced, burst, after, bones: rig.bones.length, lastTimeMs: clip.frames[clip.frames.length - 1]!.timeMs });
  rig.terminate();
}

main().catch((e: unknown) => publishError("handrig/worker", e));
