# The compressive cap (issue 20) through the whole program: a crushed joint on
# the closed form of model.md's sbar(k3), its dissipated energy, in 2D on one
# rank and in 3D on two, the perfectly plastic cap, and its bad keys
# (tests/nonlinear/check_cap.py). The kernel's own tests are unit.laws.cap_*.
bw_py_test(nonlinear.cap_crush_2d nonlinear nonlinear/check_cap.py crush 2 1)
bw_py_test(nonlinear.cap_crush_3d "nonlinear;dim3;mpi" nonlinear/check_cap.py crush 3 2)
bw_py_test(nonlinear.cap_plastic nonlinear nonlinear/check_cap.py plastic)
bw_py_test(nonlinear.cap_errors "nonlinear;errors" nonlinear/check_cap.py errors)
