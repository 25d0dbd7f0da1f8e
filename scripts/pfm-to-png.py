#!/usr/bin/env python3
"""Writes a PFM picture as the 8-bit PNG `nffrt render` would have written of the
same values: each channel clamped to [0, 1], then linear, the sRGB curve or the
course's gamma 2.2, scaled by 255 and rounded (src/image/framebuffer.rs), in
float32 as nffrt computes it. For a reference rendered once as PFM (an hour at
4096 samples) that must also be compared as the picture people see.

    scripts/pfm-to-png.py IN.pfm OUT.png [linear|srgb|gamma2.2]
"""

import struct
import sys
import zlib

import numpy as np


def read_pfm(path: str) -> np.ndarray:
    with open(path, "rb") as f:
        assert f.readline().strip() == b"PF", "a colour PFM"
        width, height = map(int, f.readline().split())
        scale = float(f.readline())
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4")
    return data.reshape(height, width, 3)[::-1].astype(np.float32)


def encode(values: np.ndarray, encoding: str) -> np.ndarray:
    v = np.clip(values, np.float32(0), np.float32(1))
    if encoding == "gamma2.2":
        v = np.power(v, np.float32(1 / 2.2), dtype=np.float32)
    elif encoding == "srgb":
        v = np.where(v <= 0.0031308, 12.92 * v, 1.055 * np.power(v, np.float32(1 / 2.4)) - 0.055).astype(np.float32)
    return np.floor(v * np.float32(255) + np.float32(0.5)).astype(np.uint8)


if __name__ == "__main__":
    source, target = sys.argv[1], sys.argv[2]
    encoding = sys.argv[3] if len(sys.argv) > 3 else "gamma2.2"
    rgb = encode(read_pfm(source), encoding)
    height, width, _ = rgb.shape
    rows = b"".join(b"\0" + rgb[y].tobytes() for y in range(height))

    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    with open(target, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))
