# What `cmake --install build --prefix P` adds beyond the libraries and headers (which
# blendbench_library installs) and the program (app/CMakeLists.txt):
#   P/share/blendbench/{models, scenarios, report/scripts, render/method_colours.json, papers/scripts,
#   results/baselines}
#     the data the program reads, laid out as in the source tree so that one relative name
#     resolves against either (io/include/blendbench/io/data_root.hpp);
#   P/lib/cmake/blendbench/  blendbenchConfig.cmake, its version file and the exported targets,
#     for find_package(blendbench CONFIG REQUIRED [COMPONENTS planner edges]).
include(CMakePackageConfigHelpers)

set(_config_dir ${CMAKE_INSTALL_LIBDIR}/cmake/blendbench)
set(_data_dir ${CMAKE_INSTALL_DATADIR}/blendbench)

# the data of the program (only built with the edges)
if(BLENDBENCH_SIM)
  install(DIRECTORY models scenarios DESTINATION ${_data_dir})
  install(DIRECTORY report/scripts/ DESTINATION ${_data_dir}/report/scripts
          FILES_MATCHING PATTERN "*.py" PATTERN "__pycache__" EXCLUDE)
  install(FILES render/method_colours.json DESTINATION ${_data_dir}/render)
  install(DIRECTORY papers/scripts/ DESTINATION ${_data_dir}/papers/scripts
          FILES_MATCHING PATTERN "*.py" PATTERN "__pycache__" EXCLUDE)
  install(DIRECTORY results/baselines/ DESTINATION ${_data_dir}/results/baselines
          FILES_MATCHING PATTERN "*.json")
endif()

# the exported targets, one file per component: the planner needs Eigen only
install(EXPORT blendbench-planner FILE blendbenchPlannerTargets.cmake NAMESPACE blendbench::
        DESTINATION ${_config_dir})
if(BLENDBENCH_SIM)
  install(EXPORT blendbench-edges FILE blendbenchEdgesTargets.cmake NAMESPACE blendbench::
          DESTINATION ${_config_dir})
  install(FILES cmake/BlendbenchMujoco.cmake DESTINATION ${_config_dir})
endif()

# the package config and its version (0.x: a new minor version may break the interface)
configure_package_config_file(cmake/blendbenchConfig.cmake.in
  ${PROJECT_BINARY_DIR}/blendbenchConfig.cmake INSTALL_DESTINATION ${_config_dir})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/blendbenchConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/blendbenchConfig.cmake ${PROJECT_BINARY_DIR}/blendbenchConfigVersion.cmake
        DESTINATION ${_config_dir})
