// Builds the dashboard into web/dist, which `brisance serve` serves at `/` (--web-dir). Every
// asset is bundled from npm packages: the page loads nothing from another origin.
// `npm run dev` serves it with hot reload and proxies the API to a running `brisance serve`
// (BRISANCE_URL, default http://127.0.0.1:8080).
import { defineConfig } from "vite";

declare const process: { env: Record<string, string | undefined> };
const api = process.env.BRISANCE_URL ?? "http://127.0.0.1:8080";

export default defineConfig({
  // Relative asset URLs: the built index.html works at `/` and under any prefix.
  base: "./",
  build: {
    outDir: "dist",
    emptyOutDir: true,
    target: "es2022",
    // three.js is ~0.6 MB minified; it is split into the player's own chunk, loaded on demand.
    chunkSizeWarningLimit: 800,
  },
  server: {
    proxy: { "/v1": api, "/openapi.yaml": api, "/healthz": api, "/readyz": api },
    // The example scenes (../scenes) and the TypeScript client (../clients) live outside web/.
    fs: { allow: [".."] },
  },
});
