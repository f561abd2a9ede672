#!/usr/bin/env python3
"""Writes u_wall.h5 for examples/u_wall.yaml: the u_wall of examples/walls3d.py.

    python3 examples/u_wall.py [GEOMETRY.h5]     # default: u_wall.h5 beside this script"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
import walls3d  # noqa: E402

if __name__ == "__main__":
    here = os.path.dirname(os.path.realpath(__file__))
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "u_wall.h5")
    make, params = walls3d.MAKERS["u_wall"]
    g = make(**params)
    g.write(out)
    print(f"{out}: {len(g.blocks)} blocks")
