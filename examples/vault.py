#!/usr/bin/env python3
"""Writes vault.h5 for examples/vault.yaml: the vault of examples/walls3d.py.

    python3 examples/vault.py [GEOMETRY.h5]     # default: vault.h5 beside this script"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
import walls3d  # noqa: E402

if __name__ == "__main__":
    here = os.path.dirname(os.path.realpath(__file__))
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "vault.h5")
    make, params = walls3d.MAKERS["vault"]
    g = make(**params)
    g.write(out)
    print(f"{out}: {len(g.blocks)} blocks")
