# Long calls: the GIL is released while they run, Ctrl-C stops them cleanly with
# KeyboardInterrupt; bench() and converge() return plain data.
import os
import signal
import subprocess
import sys
import textwrap
import threading
import time

import pytest

import dacrt
from conftest import CORNELL


def test_other_python_threads_run_while_a_render_does(cornell):
    ticks = 0
    done = threading.Event()

    def render():
        dacrt.render(cornell, spp=64, width=96, height=96, threads=1)
        done.set()

    worker = threading.Thread(target=render)
    worker.start()
    while not done.is_set():  # pure Python: runs only while the render holds no GIL
        ticks += 1
        time.sleep(0.001)
    worker.join()
    assert ticks > 20


def test_ctrl_c_stops_a_render_and_raises_keyboard_interrupt():
    # A render far too long to finish, interrupted after half a second: KeyboardInterrupt within
    # a few seconds, after which Python goes on (and renders again).
    script = textwrap.dedent(f"""
        import sys, time, dacrt
        scene = dacrt.load({CORNELL!r})
        print("rendering", flush=True)
        start = time.monotonic()
        try:
            dacrt.render(scene, spp=100000, width=256, height=256)
        except KeyboardInterrupt:
            print(f"interrupted after {{time.monotonic() - start:.2f}} s", flush=True)
            image = dacrt.render(scene, spp=1, width=8, height=8)
            print("rendered again", image.shape, flush=True)
            sys.exit(0)
        sys.exit(3)
    """)
    child = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True, env=os.environ)
    try:  # a render the signal does not stop is killed, not left running
        assert child.stdout.readline().strip() == "rendering"
        time.sleep(0.5)
        sent = time.monotonic()
        child.send_signal(signal.SIGINT)
        out, err = child.communicate(timeout=60)
    finally:
        child.kill()
        child.wait()
    assert child.returncode == 0, err
    assert "interrupted after" in out and "rendered again (8, 8, 3)" in out
    assert time.monotonic() - sent < 10


def test_bench_returns_its_results_as_data():
    report = dacrt.bench(CORNELL, rays="primary,shadow", backends="dacrt,brute", width=32,
                         height=32, repeat=2)
    rows = report["results"]
    assert {(r["backend"], r["rays"]) for r in rows} == {
        (b, t) for b in ("dacrt", "brute") for t in ("primary", "shadow")}
    for r in rows:
        assert r["count"] > 0 and len(r["intervals"]["trace_s"]["runs"]) == 2
    with pytest.raises(TypeError, match="unexpected keyword argument 'json'"):
        dacrt.bench(CORNELL, json="x.json")


def test_converge_returns_its_points_as_data():
    rows = dacrt.converge(CORNELL, config=["", "sampler=independent"], width=16, height=16,
                          no_reference=True, max_spp=4, time_budget=5)
    labels = {r.config for r in rows}
    assert labels == {"default", "sampler=independent"}
    assert all(r.spp in (1, 2, 4) for r in rows)
    assert all(r.noise > 0 for r in rows)
