# Three dimensions (issue "Walls in three dimensions"): invariants of the 3D
# code against the 2D one and closed forms.
# Extrusion invariant: 2D on 1 rank against its extrusion on 1 and 3 ranks.
# One Python process per test, each case's 2D run once for its 3D runs (it
# was a test per case and rank count, the 2D run repeated for 3 ranks).
bw_py_test(dim3.extrusion.paper "dim3;paper;mpi" dim3/check_extrusion.py
           paper_1 paper_2:1,3 paper_3 paper_4 paper_5 paper_6 paper_7 paper_8 paper_9)
bw_py_test(dim3.extrusion.wall "dim3;mpi" dim3/check_extrusion.py wall:1,3 prescribed)
# Two blocks under all six load components against model.md's closed form.
foreach(grid "16;4" "5;3" "2;2")
  list(JOIN grid "x" tag)
  bw_py_test(dim3.closed_form.${tag} dim3 dim3/check_closed_form.py ${grid})
endforeach()
bw_py_test(dim3.closed_form.5x3_2ranks "dim3;mpi" dim3/check_closed_form.py 5 3 2)
# The 3D XDMF opened by ParaView's readers: polyhedra, interface polygons, fields.
bw_py_test(dim3.xdmf_np1 "dim3;post" dim3/check_xdmf.py 1)
bw_py_test(dim3.xdmf_np3 "dim3;post;mpi" dim3/check_xdmf.py 3)
bw_py_test(dim3.xdmf_pushover "dim3;post;nonlinear" dim3/check_xdmf.py pushover)
# 3D geometry files: hulls, detection, frame independence, bad files.
foreach(case twoboxes generator rotated general errors)
  bw_py_test(dim3.file.${case} dim3 dim3/check_file.py ${case})
endforeach()
foreach(case generator rotated errors)
  bw_py_test(dim3.file.${case}_3ranks "dim3;mpi" dim3/check_file.py ${case} 3)
endforeach()
# The 3D gallery (examples/walls3d.py): closed form and an independent solver.
foreach(case cantilever u_wall vault)
  bw_py_test(gallery.${case}3d "gallery;dim3" dim3/check_gallery3d.py ${case})
endforeach()
set_tests_properties(gallery.u_wall3d PROPERTIES LABELS "gallery;dim3;mpi")
# tools/plot on a 3D result (pvpython, off-screen).
bw_py_test(dim3.plot "dim3;post" dim3/check_plot3d.py)
set_tests_properties(dim3.plot PROPERTIES RESOURCE_LOCK xvfb)
# Nonlinear joints and pushover in 3D (issue "Out-of-plane collapse"):
# closed forms, the extrusion of the 2D pushovers, ranks, bad keys.
# The short cases in two Python processes (each was a test of its own, a
# Python process of 0.3 s of CPU for a second of work); j4d's extrusion,
# 8 s, and the rank counts stay tests of their own.
bw_py_test(dim3.nonlinear.closed_forms "dim3;nonlinear" dim3/check_nonlinear3d.py
           sliding8 tilt_slide tilt_rock torsion wall_tilt errors)
bw_py_test(dim3.nonlinear.extrusion "dim3;nonlinear" dim3/check_nonlinear3d.py
           extrusion:sliding extrusion:dilatancy extrusion:overturning extrusion:softening extrusion:wall extrusion:snapback)
bw_py_test(dim3.nonlinear.extrusion_j4d "dim3;nonlinear" dim3/check_nonlinear3d.py extrusion j4d)
foreach(np 2 3)
  bw_py_test(dim3.nonlinear.ranks_${np} "dim3;nonlinear;mpi" dim3/check_nonlinear3d.py ranks ${np})
endforeach()
# The static theorem (python/blockwall/limit.py, scipy) against closed forms
# and against the pushover of the U-shaped wall on a tilting table.
foreach(case block u_wall)
  bw_py_test(dim3.limit.${case} "dim3;nonlinear;gallery" dim3/check_limit3d.py ${case})
endforeach()
# tools/plot on a 3D pushover: capacity curve and crack pattern, the warped
# blocks and the failed portions coloured by state, drawn by matplotlib (the
# fallback without ParaView) and, where it is, by pvpython (on an Xvfb of
# its own: one at a time, like the other tests that start one).
bw_py_test(dim3.plot_cracks "dim3;post;nonlinear" dim3/check_cracks3d.py matplotlib)
set_tests_properties(dim3.plot_cracks PROPERTIES TIMEOUT 400)
find_program(BW_PVPYTHON pvpython)
find_program(BW_XVFB_RUN xvfb-run)
if(BW_PVPYTHON AND BW_XVFB_RUN)
  bw_py_test(dim3.plot_cracks_pvpython "dim3;post;nonlinear;paraview" dim3/check_cracks3d.py pvpython)
  set_property(TEST dim3.plot_cracks_pvpython APPEND PROPERTY ENVIRONMENT "BW_PVPYTHON=${BW_PVPYTHON};BW_XVFB_RUN=${BW_XVFB_RUN}")
  set_tests_properties(dim3.plot_cracks_pvpython PROPERTIES RESOURCE_LOCK xvfb TIMEOUT 900)
endif()
# The iterative 3D Schur solve (CG + GAMG, the top beam eliminated) against
# S^ factored, in and out of the wall's plane, on 1 and 2 ranks.
foreach(load in out)
  bw_py_test(dim3.schur_iterative_${load} "dim3;solver" dim3/check_schur3d.py ${load} 1)
  bw_py_test(dim3.schur_iterative_${load}_2ranks "dim3;solver;mpi" dim3/check_schur3d.py ${load} 2)
  set_tests_properties(dim3.schur_iterative_${load} dim3.schur_iterative_${load}_2ranks PROPERTIES TIMEOUT 120)
endforeach()
# The displacements' round-off bound through S^'s factor (without K~
# assembled) against the whole system's, on 1 and 3 ranks.
bw_py_test(dim3.forward_bound "dim3;solver;mpi" dim3/check_forward_bound.py)
set_tests_properties(dim3.forward_bound PROPERTIES TIMEOUT 300)
