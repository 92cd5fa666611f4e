# Installs the package into a fresh prefix and runs the installed pcl_graph_denoise
# there: it must find its library (RPATH $ORIGIN/../lib...), print its usage, and denoise
# a small ASCII PCD file written here.
#   cmake -DBUILD_DIR=<build> -DWORK_DIR=<dir> -P run_cli_install_test.cmake
if(NOT BUILD_DIR OR NOT WORK_DIR)
  message(FATAL_ERROR "usage: cmake -DBUILD_DIR=<build> -DWORK_DIR=<dir> -P run_cli_install_test.cmake")
endif()
file(REMOVE_RECURSE "${WORK_DIR}")
set(prefix "${WORK_DIR}/prefix")
execute_process(COMMAND ${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${prefix}"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "install failed (${rc}):\n${out}\n${err}")
endif()
set(tool "${prefix}/bin/pcl_graph_denoise")
if(NOT EXISTS "${tool}")
  message(FATAL_ERROR "the install did not put pcl_graph_denoise in ${prefix}/bin")
endif()

execute_process(COMMAND "${tool}" -h RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out MATCHES "Usage: pcl_graph_denoise input")
  message(FATAL_ERROR "installed pcl_graph_denoise -h: exit ${rc}\n${out}\n${err}")
endif()

# A 12 x 12 grid, z a small deterministic bump pattern, with an intensity field.
set(points "")
foreach(i RANGE 11)
  foreach(j RANGE 11)
    math(EXPR bump "(${i} * 31 + ${j} * 17) % 5 - 2")
    math(EXPR intensity "${i} * 12 + ${j}")
    string(APPEND points "${i} ${j} 0.0${bump} ${intensity}\n")
  endforeach()
endforeach()
string(REPLACE "0.0-" "-0.0" points "${points}")
file(WRITE "${WORK_DIR}/grid.pcd"
  "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z intensity\n"
  "SIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 1\nWIDTH 144\nHEIGHT 1\n"
  "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 144\nDATA ascii\n${points}")
execute_process(COMMAND "${tool}" grid.pcd smooth.pcd -tikhonov -ascii
                WORKING_DIRECTORY "${WORK_DIR}"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "installed pcl_graph_denoise failed on a small cloud: exit ${rc}")
endif()
file(STRINGS "${WORK_DIR}/smooth.pcd" header REGEX "^(POINTS|FIELDS|DATA) ")
if(NOT header STREQUAL "FIELDS x y z intensity;POINTS 144;DATA ascii")
  message(FATAL_ERROR "unexpected output header: ${header}")
endif()
if(NOT err MATCHES "Step 1/1: -tikhonov .*iterations, residual")
  message(FATAL_ERROR "the installed tool did not report its step")
endif()
