"""The engine's work runs with the GIL released: other Python threads go on meanwhile, and two recognizers in two
threads give what they give alone."""

from __future__ import annotations

import threading
import time

import sva
from conftest import reading_of


def test_gil_is_released_during_evaluation(tiny, tiny_map):
    done = threading.Event()
    took = []

    def work():
        t0 = time.perf_counter()
        sva.evaluate(tiny_map, str(tiny.test), trials=300, max_readings=6, backend="cpu", threads=1)
        took.append(time.perf_counter() - t0)
        done.set()

    th = threading.Thread(target=work)
    stamps = []
    th.start()
    while not done.is_set():
        stamps.append(time.perf_counter())
        time.sleep(0.001)
    th.join()
    # Held for the whole call, the GIL would stop this loop for about the call's duration.
    gaps = [b - a for a, b in zip(stamps, stamps[1:])]
    assert took[0] > 0.05, "the evaluation is too short to tell"
    assert len(stamps) > 10 and max(gaps) < took[0] / 2


def test_recognizers_in_threads_agree_with_one_thread(tiny, tiny_map):
    sessions = tiny.session_lines()[:4]

    def run(s):
        rec = sva.Recognizer(tiny_map, backend="cpu", threads=1)
        for r in s["readings"]:
            rec.add_reading(reading_of(r))
        e = rec.estimate()
        return e.object_name, e.object_probability.tolist(), e.pose.T.tolist()

    alone = [run(s) for s in sessions]
    together = [None] * len(sessions)

    def worker(i):
        together[i] = run(sessions[i])

    threads = [threading.Thread(target=worker, args=(i,)) for i in range(len(sessions))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert together == alone


def test_one_recognizer_shared_by_threads_takes_turns(tiny, tiny_map):
    """Calls on one recognizer from several threads are serialised (no crash, every reading counted)."""
    readings = [reading_of(r) for s in tiny.session_lines() for r in s["readings"]][:12]
    rec = sva.Recognizer(tiny_map, backend="cpu", threads=1)

    def add(chunk):
        for r in chunk:
            rec.add_reading(r)
            rec.estimate(top_k=1)

    threads = [threading.Thread(target=add, args=(readings[i::3],)) for i in range(3)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert rec.reading_count() == len(readings)


CTRL_C_CHILD = """
import signal, sys, time
import sva
signal.signal(signal.SIGINT, signal.default_int_handler)
train, test = sva.simulate("tiny", train=12, test=5, seed=3)
m = sva.train(train)
print("ready", flush=True)
try:
    sva.evaluate(m, test, trials=10**7, max_readings=6, backend="cpu", threads=1)
    print("finished", flush=True)
except KeyboardInterrupt:
    print("engine interrupted", flush=True)
try:
    print("sleeping", flush=True)
    time.sleep(60)
except KeyboardInterrupt:
    print("python interrupted", flush=True)
"""


def test_ctrl_c_stops_the_engine_and_python_gets_its_handler_back():
    import os
    import signal
    import subprocess
    import sys

    p = subprocess.Popen([sys.executable, "-c", CTRL_C_CHILD], stdout=subprocess.PIPE, text=True, env=os.environ)
    try:
        assert p.stdout.readline().strip() == "ready"
        time.sleep(0.5)
        p.send_signal(signal.SIGINT)  # inside sva.evaluate: the engine stops, KeyboardInterrupt
        assert p.stdout.readline().strip() == "engine interrupted"
        assert p.stdout.readline().strip() == "sleeping"
        time.sleep(0.2)
        p.send_signal(signal.SIGINT)  # back in Python: Python's own handler
        assert p.stdout.readline().strip() == "python interrupted"
        assert p.wait(timeout=30) == 0
    finally:
        p.kill()
