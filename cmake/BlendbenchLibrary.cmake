# blendbench_library(STAGE SOURCES ... [PUBLIC ...] [PRIVATE ...])
#
# One stage of the pipeline: the library blendbench_<STAGE> with the alias blendbench::<STAGE>,
# its headers under <folder>/include/blendbench/<STAGE>/ (included as "blendbench/<STAGE>/x.hpp"),
# C++20 and the project's warnings. A stage sees only the include roots of the stages it links,
# so a lower layer that includes a higher one does not compile (tests/layering.cmake checks the
# rule on the sources as well).
#
# `cmake --install` puts the library in <prefix>/lib and its headers in
# <prefix>/include/blendbench/<STAGE>/; the target joins the export set of the package component
# named by BLENDBENCH_COMPONENT in the calling directory (planner, or edges), imported by other
# projects as blendbench::<STAGE> (cmake/blendbenchConfig.cmake.in).
function(blendbench_library stage)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC;PRIVATE" ${ARGN})
  if(NOT BLENDBENCH_COMPONENT)
    message(FATAL_ERROR "blendbench_library(${stage}): BLENDBENCH_COMPONENT is not set in ${CMAKE_CURRENT_SOURCE_DIR}")
  endif()
  set(target blendbench_${stage})
  add_library(${target} ${ARG_SOURCES})
  add_library(blendbench::${stage} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${stage} OUTPUT_NAME blendbench_${stage})
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_compile_features(${target} PUBLIC cxx_std_20)
  target_link_libraries(${target} PUBLIC ${ARG_PUBLIC} PRIVATE ${ARG_PRIVATE} $<BUILD_INTERFACE:blendbench::warnings>)
  # a sanitizer build's installed libraries need the sanitizers' run-time in whatever links them
  if(BLENDBENCH_SANITIZER_LINK_FLAGS)
    target_link_options(${target} INTERFACE $<INSTALL_INTERFACE:${BLENDBENCH_SANITIZER_LINK_FLAGS}>)
  endif()

  install(TARGETS ${target} EXPORT blendbench-${BLENDBENCH_COMPONENT}
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endfunction()
