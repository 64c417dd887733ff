## The library's layers include only those below them (STYLE.md: one direction, no
## back-references): base, sparse, cholesky, lac, backends, mesh, fem, models, surgery,
## contact, dynamics, app, reports, distributed, in this order (doc/ARCHITECTURE.md); the
## programs choose among the top ones. Run as
##   cmake -DSOURCE_DIR=<repository> -P tests/layers_point_one_way.cmake
## and fails with one line per include that points up and per folder the list leaves out.

set(layers base sparse cholesky lac backends mesh fem models surgery contact dynamics app reports distributed)
set(violations "")
# Every folder of the library has its place in the order: a new one is added to the list.
foreach(root source include/warpchol)
  file(GLOB entries RELATIVE ${SOURCE_DIR}/${root} ${SOURCE_DIR}/${root}/*)
  foreach(entry ${entries})
    if(IS_DIRECTORY ${SOURCE_DIR}/${root}/${entry})
      list(FIND layers ${entry} level)
      if(level EQUAL -1)
        list(APPEND violations "${root}/${entry}: a folder the layers do not list: give it its place in them")
      endif()
    endif()
  endforeach()
endforeach()
foreach(layer ${layers})
  list(FIND layers ${layer} level)
  file(GLOB_RECURSE files
    ${SOURCE_DIR}/include/warpchol/${layer}/*.h ${SOURCE_DIR}/source/${layer}/*.cc)
  foreach(file ${files})
    file(STRINGS ${file} includes REGEX "^[ \t]*#[ \t]*include[ \t]*<warpchol/[a-z_]+/")
    foreach(include ${includes})
      string(REGEX REPLACE ".*<warpchol/([a-z_]+)/.*" "\\1" included "${include}")
      list(FIND layers ${included} included_level)
      if(included_level GREATER level)
        file(RELATIVE_PATH name ${SOURCE_DIR} ${file})
        string(STRIP "${include}" include)
        list(APPEND violations "${name}: ${include}: ${layer} must not include ${included}, which builds on it")
      endif()
    endforeach()
  endforeach()
endforeach()

if(violations)
  string(REPLACE ";" "\n" violations "${violations}")
  message(FATAL_ERROR "${violations}")
endif()
string(REPLACE ";" ", " layers "${layers}")
message(STATUS "every layer includes only the layers below it: ${layers}")
