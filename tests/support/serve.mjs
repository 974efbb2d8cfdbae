// tests/support/serve.mjs: starts `brisance serve` processes for the node-based tests
// (tests/contract, tests/web) on a free port with a fresh data folder, and stops them.
import { spawn } from "node:child_process";
import fs from "node:fs";
import os from "node:os";
import path from "node:path";

// Starts `binary serve --port 0 --data <tmp> --workers 1 --grace-s <grace> ...extraArgs` and
// resolves once its "listening" log line gives the port. The server object keeps the last
// `keepLines` log lines (for failure reports), `exited` (a promise of {code, signal}) and `url`.
export async function startServer(binary, name, extraArgs = [], { prefix = "brisance-test", grace = 5, keepLines = 400 } = {}) {
  const data = fs.mkdtempSync(path.join(os.tmpdir(), `${prefix}-${name}-`));
  const args = ["serve", "--port", "0", "--data", data, "--workers", "1", "--grace-s", String(grace), ...extraArgs];
  const child = spawn(binary, args, { stdio: ["ignore", "ignore", "pipe"] });
  const server = { name, child, data, args, port: 0, log: [] };
  server.exited = new Promise((resolveExit) => child.on("exit", (code, signal) => resolveExit({ code, signal })));
  await new Promise((resolveStart, reject) => {
    let pending = "";
    const timer = setTimeout(() => reject(new Error(`${name}: no "listening" line within 20 s`)), 20000);
    child.stderr.on("data", (chunk) => {
      pending += chunk.toString();
      let newline;
      while ((newline = pending.indexOf("\n")) >= 0) {
        const line = pending.slice(0, newline);
        pending = pending.slice(newline + 1);
        server.log.push(line);
        if (server.log.length > keepLines) server.log.shift();
        try {
          const event = JSON.parse(line);
          if (event.msg === "listening" && !server.port) {
            server.port = event.port;
            clearTimeout(timer);
            resolveStart();
          }
        } catch {
          // not a JSON line (usage errors are plain text)
        }
      }
    });
    server.exited.then(({ code, signal }) => {
      clearTimeout(timer);
      reject(new Error(`${name}: brisance serve exited (code ${code}, signal ${signal}) before listening:\n${server.log.join("\n")}`));
    });
  });
  server.url = `http://127.0.0.1:${server.port}`;
  return server;
}

// SIGTERM, then waits up to `limitMs` for the exit: {code, signal}, or null (then SIGKILLed).
// The data folder is removed either way.
export async function stopServer(server, limitMs = 30000) {
  if (server.stopped) return server.stopResult;
  server.stopped = true;
  server.child.kill("SIGTERM");
  let timer;
  const timeout = new Promise((r) => { timer = setTimeout(() => r(null), limitMs); });
  const result = await Promise.race([server.exited, timeout]);
  clearTimeout(timer);
  if (!result) server.child.kill("SIGKILL");
  fs.rmSync(server.data, { recursive: true, force: true });
  server.stopResult = result;
  return result;
}
