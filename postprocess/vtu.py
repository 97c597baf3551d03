"""Minimal reader of the .vtu files suturesim writes (deal.II's zlib-compressed binary
VTK XML): points, cells and named point arrays, for the matplotlib pictures.

Only what the plot scripts need; open the files in ParaView for anything else.
"""
import base64
import re
import struct
import zlib

import numpy as np

_DTYPES = {"Float32": np.float32, "Float64": np.float64, "Int32": np.int32,
           "Int64": np.int64, "UInt8": np.uint8, "UInt32": np.uint32}


def _decode(attributes, text, compressed):
    dtype = _DTYPES[re.search(r'type="(\w+)"', attributes).group(1)]
    text = text.strip()
    if 'format="ascii"' in attributes:
        return np.array(text.split(), dtype=dtype)
    if not compressed:
        raw = base64.b64decode(text)
        return np.frombuffer(raw[4:], dtype=dtype)
    # header: number of blocks, block size, last block size, compressed sizes (uint32),
    # base64-encoded on its own, followed by the base64 of the compressed blocks
    header_length = 4 * 4
    first = base64.b64decode(text[:((header_length + 2) // 3) * 4])
    blocks = struct.unpack("<I", first[:4])[0]
    header_length = 4 * (3 + blocks)
    header_chars = ((header_length + 2) // 3) * 4
    header = struct.unpack("<%dI" % (3 + blocks), base64.b64decode(text[:header_chars])[:header_length])
    data = base64.b64decode(text[header_chars:])
    out, offset = [], 0
    for size in header[3:]:
        out.append(zlib.decompress(data[offset:offset + size]))
        offset += size
    return np.frombuffer(b"".join(out), dtype=dtype)


def _piece(text, compressed):
    arrays = {}
    for attributes, body in re.findall(r"<DataArray([^>]*)>(.*?)</DataArray>", text, re.S):
        name = re.search(r'Name="([^"]*)"', attributes)
        components = re.search(r'NumberOfComponents="(\d+)"', attributes)
        values = _decode(attributes, body, compressed)
        if components:
            values = values.reshape(-1, int(components.group(1)))
        key = name.group(1) if name else "points"
        arrays.setdefault(key, values)
    return arrays


def read(path):
    """Returns (points (n, 3), connectivity (flat), offsets, {name: array (n, components)}).

    A file of several pieces (one per MPI process) is read whole: the pieces' points and
    arrays one after the other, their cells renumbered to match."""
    text = open(path).read()
    compressed = "vtkZLibDataCompressor" in text[:2000]
    pieces = [_piece(p, compressed) for p in re.findall(r"<Piece.*?</Piece>", text, re.S)]
    points, connectivity, offsets = [], [], []
    arrays = {key: [values] for key, values in _piece(text[:text.find("<Piece")], compressed).items()}  # CYCLE, TIME
    n_points = n_connected = 0
    for piece in pieces:
        piece_points = np.asarray(piece.pop("points"), dtype=float)
        if "connectivity" in piece:
            connectivity.append(piece.pop("connectivity") + n_points)
            offsets.append(piece.pop("offsets") + n_connected)
            n_connected += len(connectivity[-1])
        piece.pop("types", None)
        for key, values in piece.items():
            arrays.setdefault(key, []).append(values)
        points.append(piece_points)
        n_points += len(piece_points)
    join = lambda parts: np.concatenate(parts) if parts else None  # noqa: E731
    return (np.concatenate(points), join(connectivity), join(offsets),
            {key: np.concatenate(parts) for key, parts in arrays.items()})


def series(pvd_path):
    """[(time, vtu path)] of a .pvd file."""
    import os
    folder = os.path.dirname(pvd_path)
    text = open(pvd_path).read()
    return [(float(t), os.path.join(folder, f))
            for t, f in re.findall(r'timestep="([^"]+)"[^>]*file="([^"]+)"', text)]
