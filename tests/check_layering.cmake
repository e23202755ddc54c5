cmake_minimum_required(VERSION 3.25)
# Checks that every #include "module/..." in the sources respects the layering:
#   base/ (the one trim) includes no module but itself, and every module may include it;
#   geometry/<stage>/ may include geometry/<earlier or same stage>/ only, and base/;
#   printer/ may include geometry/ and printer/; sim/ geometry/, printer/ and sim/;
#   app/ (the application layer) geometry/, printer/, sim/ and app/; host/ (the command line
#   and `mahost serve`) app/, printer/, sim/ and host/: it reaches geometry/ only through app/.
#   Run by ctest as layering/includes (cmake -P, no build needed).
# Inputs: SOURCE_DIR, STAGES (geometry's stage folders in order, ;-separated).
set(violations "")
function(check_file file allowed_modules allowed_stages)
  file(STRINGS ${file} lines REGEX "^[ \t]*#[ \t]*include[ \t]+\"[a-z_]+/")
  foreach(line IN LISTS lines)
    string(REGEX MATCH "\"([a-z_]+)/([^\"]*)\"" _ "${line}")
    set(module ${CMAKE_MATCH_1})
    set(rest ${CMAKE_MATCH_2})
    if(NOT module IN_LIST allowed_modules)
      set(violations "${violations}\n  ${file}: ${line}")
    elseif(module STREQUAL "geometry" AND allowed_stages)
      string(REGEX MATCH "^([a-z_]+)/" _ "${rest}")
      if(NOT CMAKE_MATCH_1 IN_LIST allowed_stages)
        set(violations "${violations}\n  ${file}: ${line}")
      endif()
    endif()
  endforeach()
  set(violations "${violations}" PARENT_SCOPE)
endfunction()

file(GLOB top_level_geometry ${SOURCE_DIR}/geometry/*.h ${SOURCE_DIR}/geometry/*.cpp)
foreach(file IN LISTS top_level_geometry)
  set(violations "${violations}\n  ${file}: outside geometry's stage folders")
endforeach()

set(earlier "")
foreach(stage IN LISTS STAGES)
  list(APPEND earlier ${stage})
  file(GLOB_RECURSE files ${SOURCE_DIR}/geometry/${stage}/*.h ${SOURCE_DIR}/geometry/${stage}/*.cpp)
  foreach(file IN LISTS files)
    check_file(${file} "geometry;base" "${earlier}")
  endforeach()
endforeach()
foreach(module_rule "base|base" "printer|geometry;printer;base" "sim|geometry;printer;sim;base"
                    "app|geometry;printer;sim;app;base" "host|app;printer;sim;host;base")
  string(REPLACE "|" ";" parts "${module_rule}")
  list(GET parts 0 module)
  list(SUBLIST parts 1 -1 allowed)
  file(GLOB_RECURSE files ${SOURCE_DIR}/${module}/*.h ${SOURCE_DIR}/${module}/*.cpp)
  foreach(file IN LISTS files)
    check_file(${file} "${allowed}" "")
  endforeach()
endforeach()

if(violations)
  message(FATAL_ERROR "includes that break the layering:${violations}")
endif()
message(STATUS "layering: every include respects the module and stage order")
