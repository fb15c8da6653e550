"""Timing shared by the step benchmarks: whole compiled runs timed with a
warm-up, reported per step, and the machine line printed above a table."""
import os
import platform
import time


def measure(model, t_end, dt, repeat):
    """Wall time per step [ns] of ``repeat`` runs of ``model.final(t_end, dt)``
    after one warm-up run (a list: take its median)."""
    model.final(t_end, dt)  # warm-up
    ns = []
    steps = round(t_end / dt)
    for _ in range(repeat):
        t0 = time.perf_counter()
        model.final(t_end, dt)
        ns.append((time.perf_counter() - t0) / steps * 1e9)
    return ns


def machine_line(repeat, steps):
    """The machine, core count and Python version, and what the medians are over."""
    return (f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
            f"Python {platform.python_version()}; median of {repeat} runs of {steps} steps")
