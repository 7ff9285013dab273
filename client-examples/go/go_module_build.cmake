# Builds the Go programs in module mode, offline (cmake -P; client-examples/go/CMakeLists.txt):
#   -DGO=go -DSOURCE=client-examples/go -DSTUBS=<dir of the generated lbsolid/v1 files>
#   -DGOPATH=<the GOPATH-mode build's GOPATH list> -DGOCODE=/usr/share/gocode -DWORK=<dir> -DOUT=<dir>
#   -DPROGRAMS="lbsolid-go-profiles;lbsolid-go-compare"
# The module is assembled in WORK (go.mod, v1/ with the stubs, each program's sources), and
# WORK/vendor is made of Debian's packages: a link per module of go.mod's require blocks to
# GOCODE/src/<module>, and vendor/modules.txt listing, per module, its go version (from its own
# go.mod) and the packages the programs import from it (go list -deps in GOPATH mode, which
# resolves the same packages from the same tree). Then go build -mod=vendor writes OUT/<program>.
cmake_minimum_required(VERSION 3.25)  # policies of this CMake (IN_LIST, ...)
foreach(var GO SOURCE STUBS GOPATH GOCODE WORK OUT PROGRAMS)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "go_module_build: -D${var}= missing")
  endif()
endforeach()
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}/v1" "${WORK}/vendor" "${OUT}")
file(COPY "${SOURCE}/go.mod" DESTINATION "${WORK}")
file(GLOB stubs "${STUBS}/*.go")
file(COPY ${stubs} DESTINATION "${WORK}/v1")
set(program_dirs)
foreach(program ${PROGRAMS})
  file(GLOB sources "${SOURCE}/${program}/*.go")
  file(COPY ${sources} DESTINATION "${WORK}/${program}")
  list(APPEND program_dirs "./${program}")  # go list takes relative directories, not absolute ones
endforeach()

# The packages the programs import, outside the standard library and the module itself.
execute_process(
  COMMAND ${CMAKE_COMMAND} -E env GO111MODULE=off "GOPATH=${GOPATH}" "GOCACHE=${WORK}/../gocache" GOENV=off GOFLAGS=
    ${GO} list -deps -f "{{if not .Standard}}{{.ImportPath}}{{end}}" ${program_dirs}
  WORKING_DIRECTORY "${SOURCE}" OUTPUT_VARIABLE imported RESULT_VARIABLE failed ERROR_VARIABLE errors)
if(failed)
  message(FATAL_ERROR "go_module_build: go list failed: ${errors}")
endif()
string(REPLACE "\n" ";" imported "${imported}")

file(STRINGS "${SOURCE}/go.mod" requirements REGEX "^\t[^ ]+ v[^ ]+")
set(modules_txt "")
set(covered "")
foreach(line ${requirements})
  string(REGEX MATCH "^\t([^ ]+) (v[^ ]+)" _ "${line}")
  set(module "${CMAKE_MATCH_1}")
  set(version "${CMAKE_MATCH_2}")
  if(NOT IS_DIRECTORY "${GOCODE}/src/${module}")
    message(FATAL_ERROR "go_module_build: ${module} (go.mod) is not in ${GOCODE}/src: install its Debian package")
  endif()
  get_filename_component(parent "${WORK}/vendor/${module}" DIRECTORY)
  file(MAKE_DIRECTORY "${parent}")
  file(CREATE_LINK "${GOCODE}/src/${module}" "${WORK}/vendor/${module}" SYMBOLIC)
  set(go_version "")
  if(EXISTS "${GOCODE}/src/${module}/go.mod")
    file(STRINGS "${GOCODE}/src/${module}/go.mod" go_line REGEX "^go [0-9.]+")
    if(go_line)
      string(REGEX REPLACE "^go ([0-9.]+).*" "; go \\1" go_version "${go_line}")
    endif()
  endif()
  string(APPEND modules_txt "# ${module} ${version}\n## explicit${go_version}\n")
  foreach(package ${imported})
    if(package STREQUAL module OR package MATCHES "^${module}/")
      string(APPEND modules_txt "${package}\n")
      list(APPEND covered "${package}")
    endif()
  endforeach()
endforeach()
foreach(package ${imported})
  # lbsolid/v1: the module itself; _/...: the programs (GOPATH mode names a directory outside it so)
  if(package AND NOT package MATCHES "^(lbsolid/|_/)" AND NOT package IN_LIST covered)
    message(FATAL_ERROR "go_module_build: ${package} belongs to no module of go.mod: add its module there")
  endif()
endforeach()
file(WRITE "${WORK}/vendor/modules.txt" "${modules_txt}")

foreach(program ${PROGRAMS})
  execute_process(
    COMMAND ${CMAKE_COMMAND} -E env GO111MODULE=on GOFLAGS=-mod=vendor GOPROXY=off GONOSUMDB=* GOENV=off
      "GOCACHE=${WORK}/../gocache" "GOPATH=${WORK}/../gopath-module" CGO_ENABLED=0
      ${GO} build -o "${OUT}/${program}" "./${program}"
    WORKING_DIRECTORY "${WORK}" RESULT_VARIABLE failed ERROR_VARIABLE errors)
  if(failed)
    message(FATAL_ERROR "go_module_build: go build -mod=vendor ${program} failed:\n${errors}")
  endif()
endforeach()
