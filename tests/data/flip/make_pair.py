#!/usr/bin/env python3
"""Writes the deterministic image pair for the FLIP reference test.

Standard library only. Run it from anywhere; it writes next to itself:

    python3 make_pair.py

- reference.png  48x32 RGB: a horizontal ramp in red, a vertical ramp in
                 green, a constant blue, and a white disc (radius 8) at
                 (16, 16)
- test.png       the same with the disc moved 2 pixels right, turned pale
                 yellow, and every pixel's green offset by a value from a
                 fixed linear congruential generator in [-12, 12]

The mean FLIP of the pair (LDR, 67 pixels per degree) is recorded in
tests/cli/diff.rs as NVIDIA's reference implementation reports it:

    python3 -m venv /tmp/flipvenv && /tmp/flipvenv/bin/pip install flip-evaluator
    /tmp/flipvenv/bin/flip -r reference.png -t test.png -ppd 67 -nerm
"""

import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
WIDTH, HEIGHT = 48, 32


def write_png(path, width, height, rows):
    """8-bit RGB, no interlace; `rows` is a list of lists of (r, g, b)."""

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    raw = b"".join(b"\x00" + bytes(c for px in row for c in px) for row in rows)
    png = b"\x89PNG\r\n\x1a\n"
    png += chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9))
    png += chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def clamp8(v):
    return max(0, min(255, v))


def image(disc_x, disc_color, noise):
    state = 12345
    rows = []
    for y in range(HEIGHT):
        row = []
        for x in range(WIDTH):
            r = x * 255 // (WIDTH - 1)
            g = y * 255 // (HEIGHT - 1)
            b = 64
            if (x - disc_x) ** 2 + (y - 16) ** 2 <= 64:
                r, g, b = disc_color
            if noise:
                state = (state * 1103515245 + 12345) % 2**31
                g = clamp8(g + (state >> 16) % 25 - 12)
            row.append((r, g, b))
        rows.append(row)
    return rows


write_png(os.path.join(HERE, "reference.png"), WIDTH, HEIGHT, image(16, (255, 255, 255), False))
write_png(os.path.join(HERE, "test.png"), WIDTH, HEIGHT, image(18, (255, 240, 200), True))
