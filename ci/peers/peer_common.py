"""Shared by the Python peers: timing summaries and the one JSON line each prints."""
import glob
import json
import os
import re
import statistics
import sys


def use_newest_libllvm():
    """Points Dr.Jit's LLVM backend (DRJIT_LIBLLVM_PATH) at the newest libLLVM installed,
    unless the variable names one already: Mitsuba's llvm variants need one, and LLVM 15
    cannot lower what Dr.Jit emits for point lights (LLVM 19 can)."""
    if "DRJIT_LIBLLVM_PATH" in os.environ:
        return

    def version(path):
        m = re.search(r"libLLVM[-.]?(?:so\.)?(\d+)", os.path.basename(path))
        return int(m.group(1)) if m else 0
    found = sorted(glob.glob("/usr/lib/*/libLLVM*.so*") + glob.glob("/usr/lib/llvm-*/lib/libLLVM*.so*"), key=version)
    if found:
        os.environ["DRJIT_LIBLLVM_PATH"] = found[-1]


def summary(times_s):
    """Median, min and max of the timed runs, in milliseconds."""
    ms = [t * 1e3 for t in times_s]
    return {"median_ms": round(statistics.median(ms), 3), "min_ms": round(min(ms), 3),
            "max_ms": round(max(ms), 3), "runs": len(ms)}


def int_args(names, defaults):
    """Positional integer arguments (all >= 1), with defaults; a one-line error otherwise."""
    argv = sys.argv[1:]
    if len(argv) > len(names) or any(a in ("-h", "--help") for a in argv):
        sys.exit(f"usage: {sys.argv[0]} {' '.join(n.upper() for n in names)}")
    out = []
    for i, (name, default) in enumerate(zip(names, defaults)):
        if i < len(argv):
            try:
                v = int(argv[i])
            except ValueError:
                v = 0
            if v < 1:
                sys.exit(f"{sys.argv[0]}: {name} must be a positive integer, not {argv[i]!r}")
            out.append(v)
        else:
            out.append(default)
    return out


def emit(obj):
    print(json.dumps(obj), flush=True)
