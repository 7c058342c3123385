#!/usr/bin/env python3
"""Render every case of a lightproof export with Mitsuba 3 (written by `lightproof export`).

Each case folder listed in suite.json holds scene.xml and export.json; this script writes
independent renders renders/000.exr, renders/001.exr, ... (render k uses seeds
k * passes + q, one per pass q, below) and renders/render.json (variant, samples,
seeds), removing earlier renders first.

Mitsuba's film sums a pixel's samples in float32: one render of 2^18 samples of a constant
sky of radiance 0.7 returns 0.7018 (2^20: 0.6927). So each render is made of passes of at
most --pass-spp samples per pixel (distinct seeds), averaged here in double precision.
Then:

    lightproof judge --suite THIS_FOLDER

Usage: python3 render_all.py [--variant scalar_rgb] [--renders 16] [--samples 65536] [--only SUBSTRING] [--threads N]

Variants: any Mitsuba variant whose colours are RGB (scalar_rgb, llvm_ad_rgb, cuda_ad_rgb).
The llvm_* variants need a libLLVM >= 16; if Dr.Jit does not find it, point
DRJIT_LIBLLVM_PATH at it (e.g. /usr/lib/x86_64-linux-gnu/libLLVM-19.so).
"""
import argparse
import json
import os
import sys


def positive(text):
    """An integer of at least 1 (a --pass-spp of 0 once divided by zero)."""
    try:
        n = int(text)
    except ValueError:
        n = 0
    if n < 1:
        raise argparse.ArgumentTypeError("must be a positive integer, got %r" % text)
    return n


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--variant", default="scalar_rgb", help="Mitsuba variant (default scalar_rgb)")
    p.add_argument("--renders", type=int, default=16,
                   help="independent renders per case (render k: seeds k*passes+q, one per pass q)")
    p.add_argument("--samples", type=int, default=65536, help="paths per render (spp = samples / pixels)")
    p.add_argument("--pass-spp", type=positive, default=256,
                   help="samples per pixel of one Mitsuba pass (float32 film sums)")
    p.add_argument("--only", default=None, help="render only case ids containing this text")
    p.add_argument("--threads", type=int, default=None, help="worker threads (default: all cores)")
    args = p.parse_args()
    if args.renders < 2:
        sys.exit("--renders must be at least 2: the judge estimates the error from independent renders")
    import mitsuba as mi
    mi.set_variant(args.variant)
    import drjit as dr
    if args.threads:
        dr.set_thread_count(args.threads)
    root = os.path.dirname(os.path.abspath(__file__))
    with open(os.path.join(root, "suite.json")) as f:
        suite = json.load(f)
    for cid in suite["cases"]:
        if args.only and args.only not in cid:
            continue
        d = os.path.join(root, cid)
        with open(os.path.join(d, "export.json")) as f:
            man = json.load(f)
        scene = mi.load_file(os.path.join(d, man["scene"]))
        out = os.path.join(d, "renders")
        os.makedirs(out, exist_ok=True)
        for name in os.listdir(out):
            if name.endswith(".exr") or name == "render.json":
                os.remove(os.path.join(out, name))
        pixels = man["width"] * man["height"]
        spp = max(1, -(-args.samples // pixels))
        passes = max(1, -(-spp // args.pass_spp))
        spp = passes * min(spp, args.pass_spp)
        for k in range(args.renders):
            total = None
            for q in range(passes):
                img = mi.render(scene, seed=k * passes + q, spp=spp // passes)
                shape = img.shape
                flat = img.array
                vals = [float(flat[i]) for i in range(len(flat))]
                total = vals if total is None else [a + b for a, b in zip(total, vals)]
            mean = mi.TensorXf([v / passes for v in total], shape)
            tmp = os.path.join(out, ".%03d.tmp.exr" % k)
            # Mitsuba 3.9.1 (Dr.Jit 1.5) deadlocks writing an EXR when its pool has one
            # thread (reports/mitsuba/exr_write_one_thread.py): write with two.
            if args.threads == 1:
                dr.set_thread_count(2)
            mi.util.write_bitmap(tmp, mean, write_async=False)
            if args.threads == 1:
                dr.set_thread_count(1)
            os.replace(tmp, os.path.join(out, "%03d.exr" % k))
        info = {"renderer": "mitsuba %s %s" % (mi.__version__, args.variant), "spp": spp,
                "passes": passes, "seeds": list(range(args.renders * passes))}
        with open(os.path.join(out, "render.json"), "w") as f:
            json.dump(info, f)
        print("%s: %d renders x %d spp (%d passes)" % (cid, args.renders, spp, passes), flush=True)


if __name__ == "__main__":
    main()
