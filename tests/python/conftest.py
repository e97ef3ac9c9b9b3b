import os
import sys

import numpy as np
import pytest

sys.path.insert(0, os.environ.get("ST_PYTHON_DIR", os.path.join(os.getcwd(), "python")))

EXAMPLES = os.environ.get("ST_EXAMPLES_DIR", os.path.join(os.path.dirname(__file__), "..", "..", "examples"))
TOOL = os.environ.get("ST_TOOL", os.path.join(os.getcwd(), "surgical-template"))


@pytest.fixture(scope="session")
def stk():
    import stkernel

    return stkernel


@pytest.fixture
def outdir(tmp_path):
    return tmp_path


def icosphere(radius=10.0, levels=4):
    t = (1.0 + 5 ** 0.5) / 2.0
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
         (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
         (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11),
         (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    v = [np.array(p, float) for p in v]
    for _ in range(levels):
        mid = {}

        def m(a, b):
            k = (min(a, b), max(a, b))
            if k not in mid:
                v.append((v[a] + v[b]) / 2)
                mid[k] = len(v) - 1
            return mid[k]

        nf = []
        for a, b, c in f:
            ab, bc, ca = m(a, b), m(b, c), m(c, a)
            nf += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        f = nf
    V = np.array(v)
    V = radius * V / np.linalg.norm(V, axis=1)[:, None]
    return V, np.array(f, dtype=np.int32)
