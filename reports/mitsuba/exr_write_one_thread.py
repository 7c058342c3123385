#!/usr/bin/env python3
"""Mitsuba 3.9.1 (Dr.Jit 1.5.0): with one worker thread, writing an EXR never returns.

    python3 exr_write_one_thread.py     # prints the outcome for 1 and 2 threads

Found by lightproof's render_all.py --threads 1 (every case's first render hung, 0% CPU).
The driver works around it by writing with two threads.
"""
import subprocess
import sys

CHILD = """
import sys, mitsuba as mi, drjit as dr
mi.set_variant('scalar_rgb')
dr.set_thread_count(int(sys.argv[1]))
mi.Bitmap(mi.TensorXf([1.0, 1.0, 1.0], (1, 1, 3))).write('/tmp/exr_write_one_thread.exr')
"""

for threads in (1, 2):
    try:
        subprocess.run([sys.executable, "-c", CHILD, str(threads)], timeout=30, check=True)
        print(f"{threads} thread(s): the 1x1 EXR was written")
    except subprocess.TimeoutExpired:
        print(f"{threads} thread(s): Bitmap.write still blocked after 30 s (deadlock)")
