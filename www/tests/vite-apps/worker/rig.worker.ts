// The module the Worker runs: handrig (Vite copies its .wasm) served by handrig/worker.
import * as handrig from "handrig";
import { serveRig } from "handrig/worker";

serveRig(handrig);
