"""Long solves release the GIL (two cases in two threads use two cores; Python code runs
meanwhile) and Ctrl-C interrupts them promptly."""

from __future__ import annotations

import os
import subprocess
import sys
import threading
import time
from typing import Callable, List

import pytest

import beamflow
from conftest import REPO


def long_case(periods: int) -> beamflow.Case:
    """The frame case with one transient of a fixed number of drive periods."""
    case = beamflow.Case.from_file("cases/beam-frame-12V-60Hz.toml")
    case["analysis"] = [{"type": "transient", "periods": periods, "steady_state": False}]
    return case


def seconds(fn: Callable[[], object]) -> float:
    t = time.perf_counter()
    fn()
    return time.perf_counter() - t


def in_two_threads(a: beamflow.Case, b: beamflow.Case) -> None:
    errors: List[BaseException] = []

    def work(c: beamflow.Case) -> None:
        try:
            c.run()
        except BaseException as e:  # surfaced below
            errors.append(e)

    threads = [threading.Thread(target=work, args=(c,)) for c in (a, b)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors, errors


PROCESS = """
import sys, time
import beamflow
case = beamflow.Case.from_file("cases/beam-frame-12V-60Hz.toml")
case["analysis"] = [{"type": "transient", "periods": int(sys.argv[2]), "steady_state": False}]
case.run()
while time.time() < float(sys.argv[1]):
    time.sleep(0.001)
t = time.perf_counter()
case.run()
print(time.perf_counter() - t)
"""


def in_two_processes(periods: int) -> float:
    """Wall time of the same two cases in two processes started together: what the
    machine's free cores allow at this moment, with no GIL involved."""
    start = time.time() + 1.5
    procs = [
        subprocess.Popen([sys.executable, "-c", PROCESS, str(start), str(periods)], cwd=REPO, stdout=subprocess.PIPE, text=True)
        for _ in range(2)
    ]
    return max(float(p.communicate(timeout=120)[0]) for p in procs)


@pytest.mark.skipif((os.cpu_count() or 1) < 2, reason="two threads need two cores to finish faster than one after the other")
def test_two_cases_in_two_threads_take_less_than_1_6_times_one() -> None:
    """The criterion on a quiet machine: two cases in two threads < 1.6 × one case.

    The machine is shared (other builds and tests): each measurement is the best of three,
    and a disturbed attempt is repeated. When the machine has no free second core at all
    (two *processes* also take ≥ 1.6 × one), threads cannot do better than processes; then
    the test asks that they do as well (within 15 %) and says so. A held GIL fails both:
    it serialises the threads while processes would still overlap.
    """
    periods = 300
    a, b = long_case(periods), long_case(periods)
    a.run()  # warm-up: page in the library, start the allocator
    seen, busy = [], []
    for _ in range(4):
        one = min(seconds(a.run) for _ in range(3))
        two = min(seconds(lambda: in_two_threads(a, b)) for _ in range(3))
        if two < 1.6 * one:
            print(f"one case {one:.3f} s, two in two threads {two:.3f} s ({two / one:.2f} ×)")
            return
        procs = min(in_two_processes(periods) for _ in range(2))
        seen.append(f"threads {two / one:.2f} ×, processes {procs / one:.2f} × one case ({one:.3f} s)")
        if procs >= 1.6 * one and two <= 1.25 * procs:
            busy.append(seen[-1])
        time.sleep(2.0)
    assert busy, f"two threads never took less than 1.6 × one case, though processes did: {seen}"
    print(f"NOTICE: no free second core during the measurement ({seen}); two threads did as well as two processes")


def test_python_runs_while_a_case_solves() -> None:
    """Independent of core count: the main thread keeps running Python code during a
    solve in another thread (with the GIL held, it would stall for the whole solve).
    The solve is sized from a timed short one to last about a second on any machine."""
    short = 200
    took = seconds(long_case(short).run)
    case = long_case(max(short, int(short * 1.0 / max(took, 1e-3))))
    worker = threading.Thread(target=case.run)
    gaps, last = [], time.perf_counter()
    start = last
    worker.start()
    while worker.is_alive():
        sum(range(1000))  # Python work, needs the GIL
        now = time.perf_counter()
        gaps.append(now - last)
        last = now
    worker.join()
    total = last - start
    assert total > 0.2, "the solve was too short to tell"
    assert max(gaps) < 0.25 * total, f"the main thread stalled {max(gaps):.3f} s of {total:.3f} s"


INTERRUPT = """
import os, signal, sys, threading, time
# Python raises KeyboardInterrupt only where SIGINT was not ignored when it started; a
# background job's children inherit it ignored, so the handler is set as a user's is.
signal.signal(signal.SIGINT, signal.default_int_handler)
import beamflow
what = sys.argv[1]
if what == "sweep":
    call = lambda: beamflow.sweep({"base": "cases/placement-frame.toml", "parameter": [
        {"path": "actuator[0].x_e", "start": 0.05, "stop": 0.68, "count": 400},
        {"path": "actuator[0].voltage.frequency", "start": 10.0, "stop": 500.0, "count": 400}]}, as_frame=False)
else:
    case = beamflow.Case.from_file("cases/beam-frame-12V-60Hz.toml")
    case["analysis"] = [{"type": "transient", "periods": 20000, "steady_state": False}]
    call = case.run
threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
t = time.perf_counter()
try:
    call()
    print("finished", time.perf_counter() - t)
except KeyboardInterrupt:
    print("interrupted", time.perf_counter() - t)
"""


@pytest.mark.parametrize("what", ["sweep", "case"])
def test_ctrl_c_interrupts_a_long_solve(what: str) -> None:
    done = subprocess.run([sys.executable, "-c", INTERRUPT, what], cwd=REPO, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    word, elapsed = done.stdout.split()
    # The solve alone takes several seconds (about 7 s here; long enough that a signal
    # delayed by a loaded machine still comes well before it ends); the signal comes at 0.5 s.
    assert word == "interrupted", done.stdout
    assert float(elapsed) < 1.5, f"KeyboardInterrupt came {elapsed} s after the start"
