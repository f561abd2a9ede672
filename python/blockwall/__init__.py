"""blockwall's Python side (numpy, h5py; matplotlib for the plots, ezdxf
for DXF drawings): write the geometry of your own wall, run blockwall,
read and draw its results.

    import blockwall as bw
    g = bw.Geometry(depth=0.1)
    g.add_block(bw.rectangle(0, -0.1, 1.0, 0.0), sets=["base"])
    g.add_block(bw.rectangle(0, 0.01, 1.0, 0.3), sets=["top"])
    g.write("two.h5")                                 # geometry.generator: file
    res = bw.solve("two.yaml", ranks=2)               # run blockwall, read the result
    res.displacement, res.resultant, res.solver["residual"]
    bw.plot_wall(res).figure.savefig("two.png")       # deformed wall, stresses
    bw.plot_cracks(res, "peak").figure.savefig("cracks.png")  # a pushover's crack pattern
    bw.import_dxf("wall.dxf", "wall.h5", layer_sets=True)   # a drawing -> geometry

Modules: geometry (write/read the HDF5 geometry input), polygon (the
checks blockwall makes, in Python), results (read a result file), launch
(run blockwall with mpiexec), plots and summary (pictures and the table
tools/plot prints), dxf (tools/import_dxf), accuracy (tools/error_vs_time)."""
from .geometry import Geometry, box, prism, read_geometry, rectangle, write_geometry
from .launch import RunError, RunResult, RunTimeout, call, command, environment, find_executable, run, solve, start
from .results import Results, Step, load, read, read_datasets, rigid_displacement

__version__ = "0.1.0"

_LAZY = {  # need matplotlib or ezdxf: imported on first use
    "plot_wall": "plots", "plot_interface_stress": "plots", "plot_history": "plots", "auto_scale": "plots",
    "plot_cracks": "plots", "curve_axes": "plots", "peak_step": "plots", "nearest_written_step": "plots", "portion_segments": "plots",
    "WallPlot": "plots", "StressPlot": "plots", "HistoryPlot": "plots", "CrackPlot": "plots", "summary": "summary", "summary_rows": "summary",
    "import_dxf": "dxf", "DxfError": "dxf",
}

__all__ = ["Geometry", "read_geometry", "rectangle", "write_geometry", "RunError", "RunResult", "RunTimeout", "call", "start", "command",
           "environment", "find_executable", "run", "solve", "Results", "Step", "load", "read", "read_datasets",
           "rigid_displacement", *_LAZY]


def __getattr__(name):
    if name in _LAZY:
        import importlib
        return getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
    raise AttributeError(f"module 'blockwall' has no attribute {name!r}")
