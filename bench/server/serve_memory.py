#!/usr/bin/env python3
"""Peak resident memory of `brisance serve` while it serves one large job's results.

    serve_memory.py BRISANCE SCENE.json [--form frames-json|frames-brf|glb ...]

Starts `brisance serve` on a fresh data folder with one worker, submits SCENE, waits for the job,
then for each form asks for it whole (frames: the default page, the whole run), reads the body to
the end and prints the bytes, the seconds and the server's VmHWM (peak RSS, /proc/PID/status)
before and after. Forms run in the order given, so each peak includes the ones before: give one
form per run for separate peaks. With --data DIR the store is kept for frames_memory_bench."""
import argparse, json, os, shutil, subprocess, sys, tempfile, time, urllib.request


def vm(pid, field):
    with open("/proc/%d/status" % pid) as status:
        for line in status:
            if line.startswith(field + ":"):
                return int(line.split()[1])
    return -1


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("brisance")
    parser.add_argument("scene")
    parser.add_argument("--form", action="append", default=[])
    parser.add_argument("--port", type=int, default=18917)
    parser.add_argument("--data", help="the data folder, kept afterwards (default: a temporary one)")
    args = parser.parse_args()
    data = args.data or tempfile.mkdtemp(prefix="serve-memory-")
    server = subprocess.Popen([args.brisance, "serve", "--data", data, "--port", str(args.port),
                               "--workers", "1", "--min-free-mb", "0", "--log-level", "warn"])
    base = "http://127.0.0.1:%d" % args.port
    try:
        for _ in range(100):
            try:
                urllib.request.urlopen(base + "/healthz", timeout=1)
                break
            except OSError:
                time.sleep(0.1)
        with open(args.scene) as f:
            body = json.dumps({"scene": json.load(f)}).encode()
        request = urllib.request.Request(base + "/v1/jobs", data=body,
                                         headers={"Content-Type": "application/json"})
        job = json.load(urllib.request.urlopen(request))
        started = time.time()
        while job["status"] not in ("succeeded", "failed", "cancelled"):
            job = json.load(urllib.request.urlopen(base + "/v1/jobs/%s?wait=30" % job["id"]))
        if job["status"] != "succeeded":
            sys.exit("job %s: %s" % (job["status"], job.get("error")))
        stats = job["stats"]
        print("job %s: %.1f s, stored_bytes %s, server VmHWM %d KiB after the run"
              % (job["id"], time.time() - started, stats.get("stored_bytes"),
                 vm(server.pid, "VmHWM")))
        for form in args.form or ["frames-json"]:
            path, accept = {"frames-json": ("/frames", "application/json"),
                            "frames-brf": ("/frames", "application/octet-stream"),
                            "glb": ("/result.glb", "model/gltf-binary")}[form]
            before = vm(server.pid, "VmHWM")
            start = time.time()
            request = urllib.request.Request(base + "/v1/jobs/%s%s" % (job["id"], path),
                                             headers={"Accept": accept})
            size = 0
            status = 200
            try:
                with urllib.request.urlopen(request) as response:
                    while True:
                        chunk = response.read(1 << 20)
                        if not chunk:
                            break
                        size += len(chunk)
            except urllib.error.HTTPError as error:
                status = error.code
                size = len(error.read())
            print("%-11s status %d, %d bytes in %.1f s, server VmHWM %d -> %d KiB"
                  % (form, status, size, time.time() - start, before, vm(server.pid, "VmHWM")))
    finally:
        server.terminate()
        server.wait()
        if not args.data:
            shutil.rmtree(data, ignore_errors=True)


if __name__ == "__main__":
    main()
