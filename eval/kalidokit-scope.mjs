// "Kalidokit's scope": handrig's options with what Kalidokit does not do turned off (landmark
// filtering, fingertip alignment, self-contact, wrist limits, dropout easing, the torso), so
// that both turn the same frames into finger and arm rotations. Shared by eval/speed.mjs and
// eval/instructions.mjs.
export const KALIDOKIT_SCOPE = Object.freeze({
  filter: { enabled: false },
  alignment: { enabled: false },
  contact: { enabled: false },
  arm: { wristLimits: false },
  dropout: { enabled: false },
  torso: "off",
});
