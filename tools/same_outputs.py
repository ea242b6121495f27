#!/usr/bin/env python3
"""Compares two sweep output folders of the same config (A before a change, B after it) on what a
refactor must keep: every results.json field that is not a time or computed from one (counts,
accuracy, settings, passes run and skipped), and every image's pixels (PNG image data, ignoring the
text chunks that name the build). Prints a Markdown report; exit 1 when anything differs.

Computed from times, and so left out: the roofline's rates, fractions and bound (of each entry only
its loads' units, work and source are compared) and the ray rates backend=auto measured, with the
reason that quotes them (the backend it chose and ran is compared).

A or B may name a results.json file instead of its folder: then no images are compared.

usage: tools/same_outputs.py A B"""
import gzip
import json
import os
import struct
import sys
import zlib

# Keys that are times, or where the config file lay (origin), not what was computed; telemetry is the
# device's clocks, power and temperature read around the frames, measured as the times are.
TIMING = {"origin", "frame_ms", "passes", "frame_minus_passes_ms", "warmup_s", "raybench", "analysis_s", "build_ms", "bvh_build_ms",
          "warmup_frames", "telemetry"}


def untimed(run):
    """The run without the figures computed from its times (see the docstring)."""
    run = dict(run)
    if isinstance(run.get("roofline"), dict):
        run["roofline"] = {entry: [{k: load.get(k) for k in ("unit", "work", "source")} for load in r.get("loads", [])]
                           for entry, r in run["roofline"].items() if isinstance(r, dict)}
    if isinstance(run.get("backend_choice"), dict):
        run["backend_choice"] = {k: v for k, v in run["backend_choice"].items() if k not in ("rates", "reason")}
    return run


def diff(a, b, path, out, added):
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            if k in TIMING:
                continue
            if k not in a:
                added.add(path.split("/", 1)[-1] + "/" + k if "/" in path else k)
            elif k not in b:
                out.append(f"{path}/{k}: removed")
            else:
                diff(a[k], b[k], f"{path}/{k}", out, added)
    elif isinstance(a, list) and isinstance(b, list) and len(a) == len(b):
        for i, (x, y) in enumerate(zip(a, b)):
            diff(x, y, f"{path}[{i}]", out, added)
    elif a != b:
        out.append(f"{path}: {json.dumps(a)[:80]} -> {json.dumps(b)[:80]}")


def png_pixels(path):
    data = open(path, "rb").read()
    pos, idat, header = 8, b"", b""
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            header = body
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    return header + zlib.decompress(idat)


def main():
    if len(sys.argv) != 3:
        print(__doc__.splitlines()[-1], file=sys.stderr)
        return 2
    a_dir, b_dir = sys.argv[1:]
    def results_of(path):
        if os.path.isdir(path):  # a sweep's folder, or a committed one whose results are gzipped
            gz = os.path.join(path, "results.json.gz")
            path = gz if os.path.exists(gz) else os.path.join(path, "results.json")
        with open(path, "rb") as f:
            data = f.read()
        return json.loads(gzip.decompress(data) if data[:2] == b"\x1f\x8b" else data)
    a, b = results_of(a_dir), results_of(b_dir)
    with_images = os.path.isdir(a_dir) and os.path.isdir(b_dir)
    problems, added = [], set()
    # Runs are matched by name: a run only one file has (a sweep cut short) is listed, not compared.
    b_by_name = {r["name"]: r for r in b["runs"]}
    a_names = {r["name"] for r in a["runs"]}
    only_a = [r["name"] for r in a["runs"] if r["name"] not in b_by_name]
    only_b = [r["name"] for r in b["runs"] if r["name"] not in a_names]
    problems += [f"run only in A: {n}" for n in only_a]
    print(f"# Same outputs: {a_dir} against {b_dir}\n")
    print(f"A: git {a['context'].get('tool', {}).get('git', '?')}, "
          f"B: git {b['context'].get('tool', {}).get('git', '?')}; "
          f"device {b['context'].get('device', {}).get('name', '?')}\n")
    print("Every field but times (" + ", ".join(sorted(TIMING)) + ") and what is computed from them "
          "(roofline rates, fractions and bound; backend_choice rates and reason), run by run:\n")
    print("| run | differing fields |")
    print("|---|---:|")
    for ra in a["runs"]:
        if ra["name"] not in b_by_name:
            continue
        rb = b_by_name[ra["name"]]
        out = []
        diff(untimed(ra), untimed(rb), ra["name"], out, added)
        problems += out
        print(f"| {ra['name']} | {len(out)} |")
    total_images, bad_images = 0, []
    for sub in sorted(os.listdir(a_dir)) if with_images else []:
        pa, pb = os.path.join(a_dir, sub), os.path.join(b_dir, sub)
        if not os.path.isdir(pa):
            continue
        for name in sorted(os.listdir(pa)):
            if not name.endswith(".png"):
                continue
            total_images += 1
            fb = os.path.join(pb, name)
            if not os.path.exists(fb) or png_pixels(os.path.join(pa, name)) != png_pixels(fb):
                bad_images.append(f"{sub}/{name}")
    if with_images:
        print(f"\nImages: {total_images} compared pixel for pixel, {len(bad_images)} differ.")
    else:
        print("\nImages: not compared (a results file was named, or a sweep ran with --no-images).")
    for name in bad_images:
        print(f"- differs: {name}")
    if added:
        print("\nFields B has that A has not (new keys; not a change of what A computed): " +
              ", ".join(sorted(added)))
    if only_b:
        print("\nRuns only B has (A's sweep did not finish them; not compared): " + ", ".join(only_b))
    for p in problems:
        print(f"- {p}")
    print("\nVerdict: " + ("SAME" if not problems and not bad_images else "DIFFERENT"))
    return 0 if not problems and not bad_images else 1


if __name__ == "__main__":
    sys.exit(main())
