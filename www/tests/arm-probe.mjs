// The arm probe both quick-start tests put into the page's watched applyToVRM: per frame and
// side, from the posed avatar (three-vrm's normalized bones, world space), how far each arm is
// from the T-pose (upper arm and forearm straight out; every arm, every frame), how far an arm
// at rest is from hanging down, and where a tracked hand's bone is against its image wrist.
// Page code (a string): it reads \`vrm\`, \`result\` and \`qs\` (the test's record) in its scope.
export const ARM_PROBE = `
  qs.idleFromDown ??= 0;
  qs.armFromTPose ??= 180;
  qs.seen ??= {};
  qs.track ??= { left: [], right: [] };
  vrm.scene.updateMatrixWorld(true);
  const at = (name) => vrm.humanoid.getNormalizedBoneNode(name).matrixWorld.elements.slice(12, 15);
  const deg = (u, v) => (Math.acos(Math.max(-1, Math.min(1, (u[0] * v[0] + u[1] * v[1] + u[2] * v[2]) / (Math.hypot(...u) * Math.hypot(...v))))) * 180) / Math.PI;
  for (const side of ["left", "right"]) {
    const [upper, lower, hand] = [at(side + "UpperArm"), at(side + "LowerArm"), at(side + "Hand")];
    const d = [lower[0] - upper[0], lower[1] - upper[1], lower[2] - upper[2]];
    const tracked = result.hands[side];
    // The T-pose has the upper arm and the forearm straight out (a raised hand may take the
    // upper arm out alone). Every arm, every frame: tracked, easing or at rest.
    const outward = [Math.sign(upper[0] - at("hips")[0]), 0, 0];
    const fore = [hand[0] - lower[0], hand[1] - lower[1], hand[2] - lower[2]];
    qs.armFromTPose = Math.min(qs.armFromTPose, Math.max(deg(d, outward), deg(fore, outward)));
    if (tracked) {
      if (result.ikTargets[side]) qs.track[side].push({ hand, image: qs.wristImage[tracked.index] });
      qs.seen[side] = performance.now();
    } else if (performance.now() - (qs.seen[side] ?? -Infinity) > 1000) {
      // At rest: no hand for longer than the dropout's hold and easing (250 + 500 ms).
      qs.idleFromDown = Math.max(qs.idleFromDown, deg(d, [0, -1, 0]));
    }
  }
`;
