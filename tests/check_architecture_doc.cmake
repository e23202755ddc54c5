cmake_minimum_required(VERSION 3.25)
# Checks that docs/architecture.md is the map of the source tree: it names every folder of the
# modules that holds sources (geometry/contour/ma/, host/serve/web/, ...: the folder's path from
# the repository's root, ending in "/"), and every such path it names exists; and that what it
# says of CGAL holds: "CGAL stays in N .cpp files, never in a header" with N the number of .cpp
# files that include a CGAL header, each of them named by its path, and no header including one.
# Run by ctest as docs/architecture_names_every_source_folder (cmake -P, no build needed).
# Inputs: SOURCE_DIR.
set(modules base geometry printer sim host app)
set(doc_file ${SOURCE_DIR}/docs/architecture.md)
file(READ ${doc_file} doc)

set(folders "")
foreach(module IN LISTS modules)
  if(NOT IS_DIRECTORY ${SOURCE_DIR}/${module})
    continue()
  endif()
  file(GLOB_RECURSE sources RELATIVE ${SOURCE_DIR}
       ${SOURCE_DIR}/${module}/*.h ${SOURCE_DIR}/${module}/*.cpp ${SOURCE_DIR}/${module}/*.cmake
       ${SOURCE_DIR}/${module}/*.js ${SOURCE_DIR}/${module}/*.html ${SOURCE_DIR}/${module}/*.css)
  foreach(source IN LISTS sources)
    get_filename_component(folder ${source} DIRECTORY)
    list(APPEND folders ${folder})
  endforeach()
endforeach()
list(REMOVE_DUPLICATES folders)
list(SORT folders)

set(problems "")
foreach(folder IN LISTS folders)
  # The path followed by anything but more of a name: host/serve/ is not named by host/serve/web/.
  if(NOT doc MATCHES "${folder}/([^a-z_]|$)")
    string(APPEND problems "\n  ${folder}/ holds sources but the page does not name it")
  endif()
endforeach()

string(REPLACE ";" "|" module_names "${modules}")
string(REGEX MATCHALL "(${module_names})(/[a-z_]+)*/" named "${doc}")
list(REMOVE_DUPLICATES named)
foreach(path IN LISTS named)
  if(NOT IS_DIRECTORY ${SOURCE_DIR}/${path})
    string(APPEND problems "\n  ${path} is named but does not exist")
  endif()
endforeach()

# CGAL: a file uses it when it includes <CGAL/...>.
set(cgal_sources "")
foreach(module IN LISTS modules)
  if(IS_DIRECTORY ${SOURCE_DIR}/${module})
    file(GLOB_RECURSE sources RELATIVE ${SOURCE_DIR}
         ${SOURCE_DIR}/${module}/*.h ${SOURCE_DIR}/${module}/*.cpp)
    foreach(source IN LISTS sources)
      file(STRINGS ${SOURCE_DIR}/${source} cgal_includes REGEX "^[ \t]*#[ \t]*include[ \t]*<CGAL/")
      if(cgal_includes)
        list(APPEND cgal_sources ${source})
      endif()
    endforeach()
  endif()
endforeach()
list(SORT cgal_sources)
set(cgal_cpp "")
foreach(source IN LISTS cgal_sources)
  if(source MATCHES "\\.h$")
    string(APPEND problems "\n  ${source} includes CGAL, but the page says CGAL is never in a header")
  else()
    list(APPEND cgal_cpp ${source})
    if(NOT doc MATCHES "${source}")
      string(APPEND problems "\n  ${source} includes CGAL but the page does not name it")
    endif()
  endif()
endforeach()
list(LENGTH cgal_cpp cgal_count)
set(number_words zero one two three four five six seven eight nine ten eleven twelve)
if(NOT doc MATCHES "CGAL stays in ([a-z]+|[0-9]+) \\.cpp files")
  string(APPEND problems "\n  the sentence \"CGAL stays in N .cpp files\" is missing")
else()
  set(stated "${CMAKE_MATCH_1}")
  list(FIND number_words "${stated}" stated_number)
  if(stated MATCHES "^[0-9]+$")
    set(stated_number ${stated})
  endif()
  if(NOT stated_number EQUAL cgal_count)
    string(REPLACE ";" ", " cgal_list "${cgal_cpp}")
    string(APPEND problems "\n  it says CGAL stays in ${stated} .cpp files; ${cgal_count} include it: ${cgal_list}")
  endif()
endif()

if(problems)
  message(FATAL_ERROR "${doc_file} is out of date:${problems}\n"
          "Say in it what each folder holds (one paragraph or bullet per folder) and which files use CGAL.")
endif()
