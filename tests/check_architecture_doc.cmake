cmake_minimum_required(VERSION 3.25)
# Checks that docs/architecture.md is the map of the source tree: it names every folder of the
# modules that holds sources (geometry/contour/ma/, host/serve/web/, ...: the folder's path from
# the repository's root, ending in "/"), and every such path it names exists. Run by ctest as
# docs/architecture_names_every_source_folder (cmake -P, no build needed).
# Inputs: SOURCE_DIR.
set(modules geometry printer sim host app)
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

if(problems)
  message(FATAL_ERROR "${doc_file} is out of date:${problems}\n"
          "Say in it what each folder holds (one paragraph or bullet per folder).")
endif()
