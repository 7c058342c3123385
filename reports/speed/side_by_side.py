#!/usr/bin/env python3
"""CPU cost per path of lightproof and Mitsuba 3 on the same scenes, measured interleaved.

The scenes are lightproof's bench scenes (analytic/scenes/cornell.json, furnace.json),
exported with `lightproof export --to mitsuba` so that both renderers trace the same
geometry, materials, light and estimator (path tracing with MIS, Russian roulette from
the same bounce). Each round runs, for each scene, lightproof's `estimate` (a child
process: its CPU time is read from getrusage of the children, start-up included) and
each Mitsuba variant's `mi.render` (in this process: time.process_time, every thread).
Rounds alternate the renderers so that the machine's load falls on all of them alike.
CPU time, not wall time: on a shared machine it measures what the renderer costs rather
than the other users' load. One JSON object per measurement on stdout, then a table.

Usage (from the repository root, after `cargo build --release`):

    python3 -m venv venv-mi && venv-mi/bin/pip install mitsuba==3.9.1
    apt-get install libllvm19     # for llvm_ad_rgb
    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so \\
      venv-mi/bin/python reports/speed/side_by_side.py [--rounds 2] [--paths 1048576] \\
        [--threads 2] [--variants scalar_rgb,llvm_ad_rgb] [--renders 16]
"""
import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
SCENES = ["cornell", "furnace"]


def children_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def time_lightproof(exe, case, paths, threads, seed):
    """CPU seconds of one `lightproof estimate` run, its estimate and the variance of
    one path's value (std_error² × paths)."""
    before = children_cpu()
    out = subprocess.run(
        [exe, "estimate", case, "--samples", str(paths), "--threads", str(threads),
         "--seed", str(seed)],
        check=True, capture_output=True, text=True).stdout
    cpu = children_cpu() - before
    r = json.loads(out)
    return cpu, r["estimate"], r["std_error"] ** 2 * r["samples"]


def time_mitsuba(mi, scene, pixels, paths, seed, renders):
    """CPU seconds of `renders` independent renders of paths/renders paths each, their
    mean pixel value, the variance of one path's value (the variance of the renders'
    means × the paths of one render; the red channel: R = G = B here) and the paths."""
    spp = max(1, paths // renders // pixels)
    means = []
    cpu = 0.0
    for k in range(renders):
        before = time.process_time()
        img = mi.render(scene, seed=seed * renders + k, spp=spp)
        flat = img.array
        cpu += time.process_time() - before
        means.append(sum(float(flat[i]) for i in range(0, len(flat), 3)) / pixels)
    m = sum(means) / renders
    var_of_mean = sum((x - m) ** 2 for x in means) / (renders - 1)
    return cpu, m, var_of_mean * spp * pixels, spp * pixels * renders


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--rounds", type=int, default=2)
    p.add_argument("--paths", type=int, default=1 << 20)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--variants", default="scalar_rgb,llvm_ad_rgb")
    p.add_argument("--renders", type=int, default=16,
                   help="independent Mitsuba renders per measurement (for its variance)")
    p.add_argument("--exe", default=os.path.join(ROOT, "target", "release", "lightproof"))
    args = p.parse_args()
    import mitsuba as mi
    import drjit as dr

    out = tempfile.mkdtemp(prefix="side_by_side_")
    man = {}
    for name in SCENES:
        case = os.path.join(ROOT, "analytic", "scenes", name + ".json")
        subprocess.run([args.exe, "export", case, "--to", "mitsuba", "--out",
                        os.path.join(out, name)], check=True, capture_output=True)
        with open(os.path.join(out, name, "export.json")) as f:
            man[name] = json.load(f)
        # Russian roulette from the third scattering, as lightproof's RR_DEPTH (Mitsuba
        # counts depth the same way: 1 after the first bounce; its default is 5).
        xml = os.path.join(out, name, man[name]["scene"])
        with open(xml) as f:
            text = f.read()
        text = text.replace('<integer name="max_depth" value="-1"/>',
                            '<integer name="max_depth" value="-1"/>'
                            '<integer name="rr_depth" value="3"/>')
        with open(xml, "w") as f:
            f.write(text)
    variants = [v for v in args.variants.split(",") if v]
    loaded = {}
    for v in variants:
        mi.set_variant(v)
        dr.set_thread_count(args.threads)
        for name in SCENES:
            scene = mi.load_file(os.path.join(out, name, man[name]["scene"]))
            pixels = man[name]["width"] * man[name]["height"]
            # A first render with the measured spp: the llvm variants compile their
            # kernels here (once per distinct spp), outside the timed renders.
            mi.render(scene, seed=999, spp=max(1, args.paths // args.renders // pixels))
            loaded[(v, name)] = (scene, pixels)
    rows = []
    for r in range(args.rounds):
        for name in SCENES:
            case = os.path.join(ROOT, "analytic", "scenes", name + ".json")
            cpu, est, var = time_lightproof(args.exe, case, args.paths, args.threads, r + 1)
            rows.append(dict(renderer="lightproof", scene=name, round=r, paths=args.paths,
                             cpu_s=cpu, us_per_path=1e6 * cpu / args.paths, mean=est,
                             var_per_path=var))
            print(json.dumps(rows[-1]), flush=True)
            for v in variants:
                mi.set_variant(v)
                scene, pixels = loaded[(v, name)]
                cpu, mean, var, n = time_mitsuba(mi, scene, pixels, args.paths, r + 1,
                                                 args.renders)
                rows.append(dict(renderer="mitsuba " + v, scene=name, round=r, paths=n,
                                 cpu_s=cpu, us_per_path=1e6 * cpu / n, mean=mean,
                                 var_per_path=var))
                print(json.dumps(rows[-1]), flush=True)
    # CPU seconds to a relative standard error of 10⁻³: N = var/(10⁻³ mean)² paths at
    # the measured cost per path (the work-normalised variance: a cheaper path with more
    # variance can cost more time per digit).
    for x in rows:
        x["cpu_s_to_0.1pct"] = (x["us_per_path"] * 1e-6 * x["var_per_path"]
                                / (1e-3 * x["mean"]) ** 2)
    heads = [f"{s}: µs CPU per path, relative σ of one path, CPU s to 0.1%" for s in SCENES]
    print("\n| renderer | " + " | ".join(heads) + " |")
    print("|---|" + "---|" * len(SCENES))
    for who in ["lightproof"] + ["mitsuba " + v for v in variants]:
        cells = []
        for name in SCENES:
            xs = [x for x in rows if x["renderer"] == who and x["scene"] == name]
            cells.append(" / ".join(f"{x['us_per_path']:.2f}" for x in xs) + ", "
                         + " / ".join(f"{x['var_per_path'] ** 0.5 / x['mean']:.2f}" for x in xs)
                         + ", " + " / ".join(f"{x['cpu_s_to_0.1pct']:.2f}" for x in xs))
        print(f"| {who} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    sys.exit(main())
