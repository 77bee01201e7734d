#!/usr/bin/env python3
"""The demo page end to end: serves target/web (built by `bash scripts/web-demo.sh
--build-only`), opens it in headless Chromium through chromedriver (the WebDriver protocol,
Python's standard library only), waits until the page reports FRAMES rendered frames, and
writes a screenshot. Fails on a page error, a timeout, or a screenshot that is one colour.

    python3 scripts/web-demo-check.py [OUT.png] [--frames N] [--set CONTROL=VALUE ...]

--set changes a control of the page (scene, view, estimator, preset, layout, resolution,
denoise, temporal, guard, second) once the first frame is done; FRAMES more frames must
then finish (after the scene has loaded: `--set scene=sponza` needs ../shared/scenes). The flags
that give headless Chromium WebGPU on the CPU with a canvas: --enable-unsafe-webgpu, and
Vulkan on SwiftShader for the compositor (without them the device is lost at the first
frame).
"""

import base64
import functools
import http.server
import json
import os
import socket
import subprocess
import sys
import threading
import time
import urllib.request

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def call(base, method, path, body=None):
    data = None if body is None else json.dumps(body).encode()
    req = urllib.request.Request(base + path, data=data, method=method,
                                 headers={"Content-Type": "application/json"})
    with urllib.request.urlopen(req, timeout=120) as r:
        return json.loads(r.read())["value"]


def main():
    args = sys.argv[1:]
    out = "target/web-demo.png"
    frames, sets = 3, []
    while args:
        a = args.pop(0)
        if a == "--frames":
            frames = int(args.pop(0))
        elif a == "--set":
            control, _, value = args.pop(0).partition("=")
            sets.append((control, value))
        else:
            out = a
    site = os.path.join(ROOT, "target", "web")
    if not os.path.exists(os.path.join(site, "pkg", "obscura_web.js")):
        sys.exit(f"web-demo-check: {site} is not built: run `bash scripts/web-demo.sh --build-only`")
    handler = functools.partial(http.server.SimpleHTTPRequestHandler, directory=site)
    handler.log_message = lambda *a: None
    server = http.server.ThreadingHTTPServer(("127.0.0.1", free_port()), handler)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    page = f"http://127.0.0.1:{server.server_address[1]}/"
    port = free_port()
    driver = subprocess.Popen([os.environ.get("CHROMEDRIVER", "chromedriver"), f"--port={port}"],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    base = f"http://127.0.0.1:{port}"
    browser = None
    try:
        for _ in range(100):
            try:
                call(base, "GET", "/status")
                break
            except OSError:
                time.sleep(0.1)
        caps = {"capabilities": {"alwaysMatch": {"browserName": "chrome",
                                                "goog:loggingPrefs": {"browser": "ALL"},
                                                "goog:chromeOptions": {
            "binary": os.environ.get("CHROMIUM", "/usr/bin/chromium"),
            "args": ["--headless=new", "--enable-features=Vulkan", "--use-vulkan=swiftshader", "--no-sandbox", "--enable-unsafe-webgpu",
                     "--disable-dev-shm-usage", "--disable-background-networking",
                     "--disable-component-update", "--disable-sync", "--no-first-run",
                     "--window-size=900,760", "--enable-unsafe-swiftshader", "--use-angle=swiftshader"]}}}}
        browser = call(base, "POST", "/session", caps)["sessionId"]
        s = f"/session/{browser}"
        call(base, "POST", s + "/url", {"url": page})
        script = ("const e = document.getElementById(arguments[0]); e.value = arguments[1];"
                  "e.dispatchEvent(new Event('change')); return e.value;")
        probe = ("const s = document.getElementById('status');"
                 "return [Number(s.dataset.frames || 0),"
                 " s.dataset.error || s.dataset.refused || '', s.textContent,"
                 " s.dataset.scene || 'courtyard'];")
        t0, switched, start_frames = time.time(), not sets, 0
        # A scene is fetched and loaded asynchronously: count frames from its arrival.
        want_scene = dict(sets).get("scene", "courtyard")
        while True:
            n, error, text, scene = call(base, "POST", s + "/execute/sync",
                                         {"script": probe, "args": []})
            if error:
                for entry in call(base, "POST", s + "/se/log", {"type": "browser"}):
                    print("web-demo-check: console:", entry.get("message", ""), file=sys.stderr)
                sys.exit(f"web-demo-check: the page failed after {n} frames: {error}")
            if n >= 1 and not switched:
                for control, value in sets:
                    got = call(base, "POST", s + "/execute/sync",
                               {"script": script, "args": [control, value]})
                    if got != value:
                        sys.exit(f"web-demo-check: the page has no {control} `{value}`")
                switched, start_frames = True, n
            if switched and scene != want_scene:
                start_frames = n
            elif switched and n >= start_frames + frames:
                break
            if time.time() - t0 > 600:
                sys.exit(f"web-demo-check: no {frames} frames after 600 s: {text}")
            time.sleep(0.5)
        print(f"web-demo-check: {text} ({time.time() - t0:.0f} s)", file=sys.stderr)
        png = base64.b64decode(call(base, "GET", s + "/screenshot"))
        if len(set(png[100:2000])) < 8:
            sys.exit("web-demo-check: the screenshot looks empty")
        os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
        tmp = out + ".part"
        with open(tmp, "wb") as f:
            f.write(png)
        os.replace(tmp, out)
        print(f"web-demo-check: wrote {out}", file=sys.stderr)
    finally:
        if browser:
            try:
                call(base, "DELETE", f"/session/{browser}")
            except OSError:
                pass
        driver.terminate()
        server.shutdown()


if __name__ == "__main__":
    main()
