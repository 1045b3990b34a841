# blendbench_fix_mujoco_target(): make Debian 12's mujoco::mujoco usable after find_package(mujoco).
#
# Its INTERFACE_INCLUDE_DIRECTORIES lists /usr/include/libqhull_r/ although no installed header
# needs it (the folder exists only with libqhull-dev), and CMake rejects an imported target whose
# include directory is absent. Called by the build (CMakeLists.txt) and by the installed package
# config (blendbenchConfig.cmake), so a project linking blendbench::sim gets the same target.
function(blendbench_fix_mujoco_target)
  get_target_property(includes mujoco::mujoco INTERFACE_INCLUDE_DIRECTORIES)
  if(includes)
    list(FILTER includes EXCLUDE REGEX "qhull")
    set_target_properties(mujoco::mujoco PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${includes}")
  endif()
endfunction()
