# Unit tests of the per-portion joint laws (src/kernels/joint_law_kernels.f90 through
# include/blockwall/laws.h), included from tests/CMakeLists.txt. Each case of test_laws
# checks a closed form or an invariant; the tolerances and their reasons are in the source.
add_executable(test_laws ${CMAKE_CURRENT_LIST_DIR}/test_laws.c)
target_link_libraries(test_laws PRIVATE blockwall_core)
foreach(case elastic cutoff coulomb corner apex notension soft_mode1 soft_mode2 unload tangent property bad
             cone3d extrude3d rotate3d property3d bad3d
             cap_uniaxial cap_property cap3d cap_bad)
  add_test(NAME unit.laws.${case} COMMAND test_laws ${case})
  set_tests_properties(unit.laws.${case} PROPERTIES LABELS "unit;nonlinear")
endforeach()

# The registry: laws read by name from their keys (the command line here).
add_executable(test_law_registry ${CMAKE_CURRENT_LIST_DIR}/test_law_registry.c)
target_link_libraries(test_law_registry PRIVATE blockwall_core)
add_test(NAME unit.laws.registry_mortar COMMAND test_law_registry -case mortar -joints_law mortar -joints_E 1e9 -joints_nu 0.25 -joints_thickness 0.02 -joints_head_E 2e9)
add_test(NAME unit.laws.registry_dry COMMAND test_law_registry -case dry -joints_law dry -joints_kn 3e9 -joints_kt 1e9)
add_test(NAME unit.laws.registry_elastic COMMAND test_law_registry -case elastic -joints_law dry -joints_kn 3e9 -joints_kt 1e9)
add_test(NAME unit.laws.registry_coulomb COMMAND test_law_registry -case coulomb -joints_law dry -joints_kn 8.2e10 -joints_kt 3.6e10
         -joints_strength_tension 0.25e6 -joints_strength_cohesion 0.35e6 -joints_strength_friction 0.75 -joints_strength_dilatancy 0.2
         -joints_strength_tension_energy 18 -joints_strength_shear_energy 125)
set_tests_properties(unit.laws.registry_mortar unit.laws.registry_dry unit.laws.registry_elastic unit.laws.registry_coulomb PROPERTIES LABELS "unit;nonlinear")
