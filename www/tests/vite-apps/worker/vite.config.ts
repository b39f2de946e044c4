import { defineConfig } from "vite";

// Module workers as ES modules (Vite's default worker format is iife).
export default defineConfig({ worker: { format: "es" } });
