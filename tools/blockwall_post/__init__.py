"""Post-processing of blockwall's HDF5 result files (numpy, h5py, matplotlib).

    res = load("out/wall.h5")              # the datasets and attributes
    wall = plot_wall(res, color="umag")    # deformed wall, blocks and joints coloured
    diag = plot_interface_stress(res, 0)   # normal and shear stress along interface 0
    print(summary(res))                    # root and /solver attributes

Every plot function returns the figure together with the numbers it drew
(WallPlot, StressPlot), so tests compare them with the HDF5 datasets
instead of looking at pixels. `tools/plot` is the command line front end."""
from .results import Results, load, rigid_displacement
from .plots import StressPlot, WallPlot, auto_scale, plot_interface_stress, plot_wall
from .summary import summary, summary_rows

__all__ = ["Results", "load", "rigid_displacement", "WallPlot", "StressPlot", "auto_scale",
           "plot_wall", "plot_interface_stress", "summary", "summary_rows"]
