"""pvbatch side of tests/guards/test_guards.py: opens a guard_failure.xmf with ParaView's XDMF reader and writes what
it loaded as JSON: per block the points, cells, bounds and the sum of the "flagged" field."""
import argparse
import json

from paraview.simple import XDMFReader, servermanager

ap = argparse.ArgumentParser(description=__doc__)
ap.add_argument("xmf", help="the run's guard_failure.xmf")
ap.add_argument("result", help="JSON file to write")
cli = ap.parse_args()
reader = XDMFReader(FileNames=[cli.xmf])
reader.UpdatePipeline()
data = servermanager.Fetch(reader)
blocks = []
for b in range(data.GetNumberOfBlocks()):
    blk = data.GetBlock(b)
    flag = blk.GetPointData().GetArray("flagged") or blk.GetCellData().GetArray("flagged")
    total = sum(flag.GetTuple1(i) for i in range(flag.GetNumberOfTuples())) if flag else None
    blocks.append({"type": type(blk).__name__, "points": blk.GetNumberOfPoints(), "cells": blk.GetNumberOfCells(),
                   "bounds": list(blk.GetBounds()), "flagged": total})
with open(cli.result, "w") as f:
    json.dump(blocks, f)
