"""Shared by the Python peers: timing summaries and the one JSON line each prints."""
import json
import statistics
import sys


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
