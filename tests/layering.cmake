# The layering rule of the source tree, checked on the sources:
#
#   cmake -P tests/layering.cmake <root>
#
# scans every .hpp and .cpp under the stage folders of <root> (planner/<stage>/, io/, sim/,
# render/, report/, papers/, app/; tests/, bench/ and examples/ are not stages) and fails, naming
# file, line and include, when a file
#   - includes "blendbench/<stage>/..." of a stage its folder may not depend on (docs/development.md, Layout:
#     dependencies point one way, from the planner's core out to app), or of no known stage;
#   - includes a framework's header outside the folders allowed to use it: MuJoCo in sim and
#     render, libyaml (yaml.h), yaml-cpp and urdfdom (urdf_*, console_bridge) in io, GL (OSMesa) in render,
#     nlohmann-json in report, papers and app, CLI11 in app, expat (the XML files' checks before
#     urdfdom and MuJoCo read them) in io and sim. So the planner stays Eigen-only and
#     sim reads no YAML.
# Only include directives that start a line are read (the tree is formatted that way).

cmake_minimum_required(VERSION 3.25)

if(CMAKE_ARGC LESS 4)
  message(FATAL_ERROR "usage: cmake -P tests/layering.cmake <root>")
endif()
get_filename_component(root "${CMAKE_ARGV3}" ABSOLUTE)
if(NOT IS_DIRECTORY "${root}")
  message(FATAL_ERROR "layering: ${root} is not a folder")
endif()

# the stages a folder's files may include, besides their own
set(planner_stages core geometry program corner timing robot)
set(may_core "")
set(may_geometry core)
set(may_program core geometry)
set(may_corner core geometry program)
set(may_timing core geometry program corner)
set(may_robot core)
set(may_io ${planner_stages})
set(may_sim ${planner_stages})
set(may_render ${planner_stages} sim)
set(may_report ${planner_stages})
set(may_papers ${planner_stages} io sim report)
set(may_app ${planner_stages} io sim render report papers)
set(stages ${planner_stages} io sim render report papers app)

# frameworks by the first part of the header's path, and the stages that may include them
set(frameworks mujoco yaml yaml-cpp urdf_parser urdf_model urdf_world urdf_sensor urdf_exception console_bridge GL nlohmann CLI expat)
set(users_mujoco sim render)
set(users_yaml-cpp io)
set(users_yaml io)
foreach(urdf urdf_parser urdf_model urdf_world urdf_sensor urdf_exception console_bridge)
  set(users_${urdf} io)
endforeach()
set(users_GL render)
set(users_nlohmann report papers app)
set(users_CLI app)
set(users_expat io sim)

set(violations "")
set(scanned 0)
foreach(stage IN LISTS stages)
  if(stage IN_LIST planner_stages)
    set(folder planner/${stage})
  else()
    set(folder ${stage})
  endif()
  file(GLOB_RECURSE files LIST_DIRECTORIES false "${root}/${folder}/*.hpp" "${root}/${folder}/*.cpp")
  list(SORT files)
  foreach(file IN LISTS files)
    math(EXPR scanned "${scanned} + 1")
    file(RELATIVE_PATH name "${root}" "${file}")
    file(READ "${file}" rest)
    set(rest "\n${rest}")
    set(line 0)
    # each "#include" at the start of a line: its line number from the newlines before it
    while(TRUE)
      string(FIND "${rest}" "\n#include" at)
      if(at EQUAL -1)
        break()
      endif()
      string(SUBSTRING "${rest}" 0 ${at} before)
      string(REGEX MATCHALL "\n" newlines "${before}")
      list(LENGTH newlines n)
      math(EXPR line "${line} + ${n} + 1")
      math(EXPR start "${at} + 1")
      string(SUBSTRING "${rest}" ${start} -1 rest)
      string(FIND "${rest}" "\n" end)
      string(SUBSTRING "${rest}" 0 ${end} directive)
      if(NOT directive MATCHES "^#include[ \t]*[<\"]([^>\"]+)[>\"]")
        continue()
      endif()
      set(header "${CMAKE_MATCH_1}")
      # a project header: blendbench/<stage>/...
      if(header MATCHES "^blendbench/([^/]+)/")
        set(target "${CMAKE_MATCH_1}")
        if(NOT target IN_LIST stages)
          list(APPEND violations "${name}:${line}: includes \"${header}\": no stage is named '${target}'")
        elseif(NOT target STREQUAL stage AND NOT target IN_LIST may_${stage})
          string(REPLACE ";" ", " may "${may_${stage}}")
          if(may STREQUAL "")
            set(may "none")
          endif()
          list(APPEND violations
               "${name}:${line}: includes \"${header}\": ${folder} may include only its own headers and those of: ${may}")
        endif()
        continue()
      endif()
      # a framework header: its first path part (mujoco/mujoco.h -> mujoco, mujoco.h -> mujoco)
      string(REGEX REPLACE "/.*$" "" first "${header}")
      string(REGEX REPLACE "\\.(h|hpp)$" "" first "${first}")
      if(first IN_LIST frameworks AND NOT stage IN_LIST users_${first})
        string(REPLACE ";" ", " users "${users_${first}}")
        list(APPEND violations "${name}:${line}: includes <${header}>: ${first} belongs only in: ${users}")
      endif()
    endwhile()
  endforeach()
endforeach()

if(scanned EQUAL 0)
  message(FATAL_ERROR "layering: no .hpp or .cpp under the stage folders of ${root}")
endif()
list(LENGTH violations count)
if(count GREATER 0)
  foreach(v IN LISTS violations)
    message("${v}")
  endforeach()
  message("layering: ${count} include(s) break the layering rule (${scanned} files scanned under ${root})")
  message(FATAL_ERROR "layering: failed")
endif()
message(STATUS "layering: ${scanned} files under ${root} follow the layering rule")
