#!/usr/bin/python3
"""The eigenvalues nearest zero of the tissue's tangent matrices an accurate run dumped,
and the node each lowest mode sits on. docs/tearing.md ("Why the coupled solve fails
there") reads the stitch's torn hole with it. The matrices come from PETSc's own options,
which the environment passes without touching the scene (so a restart accepts them):

  cp -a OUTPUT REPLAY    # the replay writes its own checkpoints over the one it starts from
  PETSC_OPTIONS="-suturesim_ksp_view_mat binary:K.bin" build/suturesim SCENE ... --restart REPLAY
  /usr/bin/python3 postprocess/tangent_eigenvalues.py K.bin --checkpoint OUTPUT/checkpoint \\
      --vtu OUTPUT/tissue_00061.vtu --node=-3.665,0,2

Each linear solve writes its matrix K: the tissue's tangent without the coupled bodies'
and the spread points' low-rank part (TissueModel::low_rank_update()). Repeated matrices
(the same K solved again) are named, not recomputed. For each other one: its asymmetry,
the eigenvalues of its symmetric part nearest zero (SciPy's eigsh, shift-invert about 0;
N/m), and, with --checkpoint and --vtu, the node carrying the largest share of the lowest
mode, its share of the mode's norm squared and its reference position (mm). The DoFs are
located by matching the checkpoint's displacement vector, three per node, to the VTU's
displacements (that VTU must be the checkpoint's state); one process's run only.
"""
import argparse
import hashlib
import os
import struct
import sys

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla
from scipy.spatial import cKDTree

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import vtu  # noqa: E402

MAT_CLASSID = 1211216  # PETSc's binary header of a matrix


def matrices(path, skip=0):
    """(index, CSR matrix) for each matrix of a PETSc binary file (big-endian, 32-bit
    indices), the first @p skip passed over unread."""
    with open(path, "rb") as f:
        k = 0
        while True:
            head = np.fromfile(f, dtype=">i4", count=4)
            if len(head) < 4:
                return
            classid, rows, cols, nonzeros = (int(v) for v in head)
            if classid != MAT_CLASSID:
                sys.exit("tangent_eigenvalues.py: %s: entry %d is not a matrix (class id %d)" % (path, k, classid))
            if k < skip:
                f.seek(4 * rows + 12 * nonzeros, 1)
                k += 1
                continue
            lengths = np.fromfile(f, dtype=">i4", count=rows)
            columns = np.fromfile(f, dtype=">i4", count=nonzeros)
            values = np.fromfile(f, dtype=">f8", count=nonzeros)
            if len(values) < nonzeros:
                return  # the file of a run still writing, cut mid-matrix
            pointers = np.concatenate(([0], np.cumsum(lengths)))
            yield k, sp.csr_matrix((values.astype(float), columns.astype(np.int64), pointers), shape=(rows, cols))
            k += 1


def cbor(data, at=0):
    """(value, next offset) of the CBOR item at @p at: the subset nlohmann::json writes
    (maps, arrays, text, byte strings, integers, floats, true/false/null)."""
    major, info = data[at] >> 5, data[at] & 31
    at += 1
    if major == 7:
        if info in (20, 21, 22):
            return {20: False, 21: True, 22: None}[info], at
        size, code = {25: (2, ">e"), 26: (4, ">f"), 27: (8, ">d")}[info]
        return struct.unpack(code, data[at:at + size])[0], at + size
    if info < 24:
        n = info
    else:
        size = {24: 1, 25: 2, 26: 4, 27: 8}[info]
        n = int.from_bytes(data[at:at + size], "big")
        at += size
    if major == 0:
        return n, at
    if major == 6:  # a tag (a byte string's subtype): the item it tags
        return cbor(data, at)
    if major == 1:
        return -1 - n, at
    if major in (2, 3):
        raw = data[at:at + n]
        return (raw if major == 2 else raw.decode()), at + n
    if major == 4:
        items = []
        for _ in range(n):
            item, at = cbor(data, at)
            items.append(item)
        return items, at
    if major == 5:
        entries = {}
        for _ in range(n):
            key, at = cbor(data, at)
            entries[key], at = cbor(data, at)
        return entries, at
    sys.exit("tangent_eigenvalues.py: CBOR major type %d not read here" % major)


def node_positions(checkpoint, vtu_path):
    """The reference position of each node (DoFs 3n, 3n+1, 3n+2), from the checkpoint's u
    matched to the VTU's displacements."""
    with open(os.path.join(checkpoint, "rank-0.cbor"), "rb") as f:
        state, _ = cbor(f.read())
    u = np.frombuffer(state["u"], dtype="<f8")
    if len(u) % 3:
        sys.exit("tangent_eigenvalues.py: %d DoFs are not three per node" % len(u))
    points, _, _, arrays = vtu.read(vtu_path)
    reference, first = np.unique(np.round(points, 12), axis=0, return_index=True)
    displacement = arrays["displacement"].astype(float)[first]
    distance, nearest = cKDTree(displacement).query(u.reshape(-1, 3))
    scale = np.abs(displacement).max()
    if distance.max() > 1e-6 * scale:
        sys.exit("tangent_eigenvalues.py: the checkpoint's displacements are not the VTU's (largest mismatch %.3g m "
                 "of %.3g m): give the VTU of the checkpoint's time" % (distance.max(), scale))
    return reference[nearest]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("matrices", help="a PETSc binary file of matrices (-ksp_view_mat binary:FILE)")
    parser.add_argument("--checkpoint", help="the run's checkpoint folder the dumping run started from")
    parser.add_argument("--vtu", help="the tissue VTU of that checkpoint's time")
    parser.add_argument("--eigenvalues", type=int, default=6, help="how many nearest zero")
    parser.add_argument("--skip", type=int, default=0, help="matrices to pass over first")
    parser.add_argument("--node", help="x,y,z (mm, reference): also the eigenvalues of the nearest node's own 3x3 "
                        "block of each K (needs --checkpoint and --vtu)")
    args = parser.parse_args()
    if bool(args.checkpoint) != bool(args.vtu):
        sys.exit("tangent_eigenvalues.py: --checkpoint and --vtu go together")
    nodes = node_positions(args.checkpoint, args.vtu) if args.checkpoint else None
    if args.node and nodes is None:
        sys.exit("tangent_eigenvalues.py: --node needs --checkpoint and --vtu")
    block = None
    if args.node:
        at = 1e-3 * np.array([float(x) for x in args.node.split(",")])
        block = int(np.argmin(np.linalg.norm(nodes - at, axis=1)))
        print("node's block: the node at (%s) mm" % ", ".join("%.3f" % (1e3 * x) for x in nodes[block]))
    seen = {}
    for k, K in matrices(args.matrices, args.skip):
        key = hashlib.md5(K.data.tobytes()).hexdigest()
        if key in seen:
            print("%d: as %d" % (k, seen[key]))
            continue
        seen[key] = k
        asymmetry = abs(K - K.T).max() / abs(K).max()
        values, modes = sla.eigsh(((K + K.T) / 2).tocsc(), k=args.eigenvalues, sigma=0, which="LM")
        order = np.argsort(values)
        line = "%d: asymmetry %.1e, eigenvalues [N/m] %s" % (k, asymmetry, " ".join("%.4g" % v for v in values[order]))
        if nodes is not None and len(nodes) * 3 == K.shape[0]:
            share = (modes[:, order[0]].reshape(-1, 3) ** 2).sum(axis=1)
            top = int(np.argmax(share))
            line += "; lowest mode %.0f %% on the node at (%s) mm" % (
                100 * share[top], ", ".join("%.3f" % (1e3 * x) for x in nodes[top]))
        if block is not None:
            dofs = [3 * block, 3 * block + 1, 3 * block + 2]
            B = K[dofs][:, dofs].toarray()
            line += "; node's block [N/m] %s" % " ".join("%.4g" % v for v in np.linalg.eigvalsh((B + B.T) / 2))
        print(line, flush=True)


if __name__ == "__main__":
    main()
