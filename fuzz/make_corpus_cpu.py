#!/usr/bin/env python3
"""Writes the seed corpus of fuzz_detect_cpu (fuzz/corpus_cpu/); see fuzz_detect_cpu.cc for the layout.

    fuzz/make_corpus_cpu.py [DIR]   (default: fuzz/corpus_cpu next to this file)

Check what a seed draws and finds with the replay:
    ELLIPSEKIT_FUZZ_VERBOSE=1 ELLIPSEKIT_FUZZ_PGM=/tmp/f.pgm build/bin/fuzz_detect_cpu_replay FILE
"""
import os
import struct
import sys

STRUCTURED, NULL_DATA, BAD_SIZE, SMALL_STRIDE, TWICE = 1, 2, 4, 8, 16
CAP_ARCS, CAP_PAIRS, CAP_TRIPLETS, CAP_CANDIDATES, CAP_MEAN_SHIFT = 1, 2, 4, 8, 16
NO_PAIR_CANDIDATES, ARC_CHORDS, NO_REFINE = 32, 64, 128


def header(flags, w, h, pad=0, caps=0, small=0, edits=()):
    """edits: (field byte, signed 16-bit value) pairs; field >= 0xE0 is EditOptionMore."""
    out = bytes([flags, (w - 1) % 128, (h - 1) % 96, pad, caps, small, len(edits)])
    for field, value in edits:
        out += bytes([field]) + struct.pack('<h', value)
    return out


def place(pos, extent):
    """The byte (and sub-pixel nibble) that puts a centre at pos px in a frame `extent` px wide."""
    t = (pos + 8) * 256.0 / (extent + 16)
    byte = int(t)
    return byte, min(15, int((t - byte) * 16))


def shape(w, h, cx, cy, a, b, theta_byte, gray, ring=0, blur=0):
    bx, fx = place(cx, w)
    by, fy = place(cy, h)
    return bytes([bx, by, int(round((a - 1.5) * 2)), int(round((b - 1.5) * 2)), theta_byte, gray,
                  (blur << 4) | ring, (fy << 4) | fx])


def frame(background, noise, shapes, grid=None):
    out = bytes([background, noise, len(shapes)]) + b''.join(shapes)
    return out + (grid if grid is not None else b'\0')


def grid(w, h, rows, cols, x0, y0, pitch_x, pitch_y, radius4, shape_byte, gray, shear=128, rings=False,
         checker=False, ring_byte=0):
    flags = rows | (cols << 3) | (0x40 if rings else 0) | (0x80 if checker else 0)
    return bytes([flags, place(x0, w)[0], place(y0, h)[0], pitch_x - 3, pitch_y - 3, radius4, shape_byte, gray,
                  shear]) + (bytes([ring_byte]) if rings else b'')


def noise_bytes(n, seed):
    x, out = seed, bytearray()
    for _ in range(n):
        x = (1103515245 * x + 12345) & 0x7FFFFFFF
        out.append(x >> 16 & 0xFF)
    return bytes(out)


def seeds():
    w, h = 128, 96
    yield 'grid_4x3_dots', header(STRUCTURED, w, h) + frame(
        200, 3, [], grid(w, h, 3, 4, 20, 18, 29, 29, 40, 0x0F, 30)) + noise_bytes(61, 1)
    yield 'grid_3x3_rings_checker_shear', header(STRUCTURED, w, h) + frame(
        128, 2, [], grid(w, h, 3, 3, 24, 18, 34, 28, 40, 0x2A, 240, shear=150, rings=True, checker=True,
                        ring_byte=4)) + noise_bytes(37, 2)
    yield 'rings_can', header(STRUCTURED, w, h) + frame(90, 4, [
        shape(w, h, 64, 50, 40, 22, 0, 230, ring=6),
        shape(w, h, 64, 50, 32, 17, 0, 40, ring=4),
        shape(w, h, 20, 20, 12, 12, 0, 250, ring=3, blur=2),
    ]) + noise_bytes(53, 3)
    yield 'ellipses_overlap', header(STRUCTURED, w, h) + frame(120, 5, [
        shape(w, h, 40, 40, 30, 18, 40, 220),
        shape(w, h, 80, 55, 25, 14, 200, 20, blur=3),
        shape(w, h, 100, 25, 16, 10, 100, 250),
        shape(w, h, 30, 80, 14, 14, 0, 10),
    ]) + noise_bytes(41, 4)
    # Small caps: max_pairs 3, max_triplets 3 (and a second detect() of the same frame).
    yield 'grid_4x3_on_ellipse_small_caps_twice', header(STRUCTURED | TWICE, w, h, caps=CAP_PAIRS | CAP_TRIPLETS, small=2) + \
        frame(30, 2, [shape(w, h, 64, 48, 50, 40, 30, 90)], grid(w, h, 3, 4, 18, 17, 30, 30, 38, 0x0F, 240)) + \
        noise_bytes(29, 5)
    yield 'ellipses_arc_chords_no_refine', header(
        STRUCTURED, 96, 72, pad=5, caps=ARC_CHORDS | NO_REFINE | CAP_CANDIDATES | CAP_MEAN_SHIFT, small=1) + frame(
        180, 0, [shape(96, 72, 48, 36, 30, 20, 64, 20, ring=8), shape(96, 72, 20, 20, 9, 7, 0, 60)])
    # Edits of the later options: min_edge_coverage 0, rim_min_coverage 0.4, min_axis_ratio 0.05.
    yield 'rings_more_options', header(STRUCTURED, 80, 64, edits=((0xE1, 0), (0xE4, 400), (0xE3, 50))) + frame(
        140, 1, [shape(80, 64, 40, 32, 24, 20, 10, 250, ring=5), shape(80, 64, 40, 32, 28, 24, 10, 20, ring=2)])
    # A small frame with small shapes: min_curve_points (T_n, EditOption 4) 8, max_arcs 9.
    yield 'small_64x48_min_curve_points_8', header(STRUCTURED, 64, 48, caps=CAP_ARCS, small=8, edits=((4, 8),)) + \
        frame(70, 2, [shape(64, 48, 20, 22, 11, 8, 30, 210), shape(64, 48, 46, 26, 9, 9, 0, 10, ring=3)],
              grid(64, 48, 2, 3, 40, 8, 9, 30, 12, 0x0F, 240)) + noise_bytes(19, 8)
    yield 'raw_noise_64x48', header(0, 64, 48, pad=3) + noise_bytes(300, 6)
    # Invalid: pair_reach 0 (EditOptionMore 9); a stride below the width; null data.
    yield 'invalid_option_nan', header(STRUCTURED, 32, 32, edits=((0xE9, 0),)) + frame(100, 0, [])
    yield 'invalid_small_stride', header(SMALL_STRIDE, 40, 30) + noise_bytes(16, 7)
    yield 'invalid_null_data', header(STRUCTURED | NULL_DATA, 40, 30) + frame(100, 0, [])


def main():
    out_dir = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                                  'corpus_cpu')
    os.makedirs(out_dir, exist_ok=True)
    for name, data in seeds():
        with open(os.path.join(out_dir, name), 'wb') as f:
            f.write(data)
        print(f'{name}: {len(data)} bytes')


if __name__ == '__main__':
    main()
