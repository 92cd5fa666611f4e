# Renders two generated clouds side by side under Xvfb and checks the PNG; a missing
# input file must fail without writing one.
#   cmake -DRENDER_VIEWS=<render_views> -DWORK_DIR=<dir> -P run_render_views_test.cmake
if(NOT RENDER_VIEWS OR NOT WORK_DIR)
  message(FATAL_ERROR "usage: cmake -DRENDER_VIEWS=<exe> -DWORK_DIR=<dir> -P run_render_views_test.cmake")
endif()
find_program(XVFB_RUN xvfb-run)
if(NOT XVFB_RUN)
  message(FATAL_ERROR "xvfb-run not found: render_views needs an X server "
                      "(apt-get install xvfb xauth)")
endif()
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")

# Two ASCII PCD files on a 20 x 20 grid (integer units): a bumpy paraboloid with its
# distance to the smooth one, and the smooth one, organised, with a few NaN holes.
set(noisy_points "")
set(smooth_points "")
foreach(i RANGE 19)
  foreach(j RANGE 19)
    math(EXPR x "${i} * 10 - 95")
    math(EXPR y "${j} * 10 - 95")
    math(EXPR z "((${i} - 10) * (${i} - 10) + (${j} - 10) * (${j} - 10)) / 2")
    math(EXPR bump "(${i} * 31 + ${j} * 17) % 9 - 4")
    math(EXPR zn "${z} + ${bump}")
    math(EXPR d "${bump} * ${bump}")
    math(EXPR hole "(${i} + ${j}) % 7")
    string(APPEND noisy_points "${x} ${y} ${zn} ${d}\n")
    if(hole EQUAL 0 AND i LESS 6)
      string(APPEND smooth_points "nan nan nan nan\n")
    else()
      math(EXPR ds "(${i} * ${j}) % 3")
      string(APPEND smooth_points "${x} ${y} ${z} ${ds}\n")
    endif()
  endforeach()
endforeach()
foreach(name noisy smooth)
  if(name STREQUAL "noisy")
    set(layout "WIDTH 400\nHEIGHT 1")
  else()
    set(layout "WIDTH 20\nHEIGHT 20")
  endif()
  file(WRITE "${WORK_DIR}/${name}.pcd"
    "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z distance\n"
    "SIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 1\n${layout}\nVIEWPOINT 0 0 0 1 0 0 0\n"
    "POINTS 400\nDATA ascii\n${${name}_points}")
endforeach()

include("${CMAKE_CURRENT_LIST_DIR}/xvfb.cmake")
set(code_file "${WORK_DIR}/exit_code")
xvfb_launcher(xvfb "${code_file}")

# Two views, default size 1600x800.
set(png "${WORK_DIR}/views.png")
execute_process(
  COMMAND ${xvfb} "${RENDER_VIEWS}" "${png}" noisy "${WORK_DIR}/noisy.pcd"
          smoothed "${WORK_DIR}/smooth.pcd"
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 300)
xvfb_exit_code(rc "${code_file}")
message("${out}${err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "render_views failed with ${rc}")
endif()
if(NOT EXISTS "${png}")
  message(FATAL_ERROR "render_views did not write ${png}")
endif()
# About 35 kB with the clouds, 14 kB with the labels and the colour bar alone.
file(SIZE "${png}" size)
if(size LESS 20000)
  message(FATAL_ERROR "${png} is only ${size} bytes: blank picture?")
endif()
# PNG signature, then the IHDR width and height (big-endian): 1600 x 800.
file(READ "${png}" signature LIMIT 8 HEX)
file(READ "${png}" dims OFFSET 16 LIMIT 8 HEX)
if(NOT signature STREQUAL "89504e470d0a1a0a" OR NOT dims STREQUAL "0000064000000320")
  message(FATAL_ERROR "${png} is not a 1600x800 PNG (signature ${signature}, size ${dims})")
endif()
if(NOT out MATCHES "1600x800, non-background pixels: [0-9.]+% \\(noisy\\), [0-9.]+% \\(smoothed\\)")
  message(FATAL_ERROR "render_views did not report the coverage of both views")
endif()

# Three views and every option: 1200 x 500 (0x4b0 x 0x1f4).
set(png "${WORK_DIR}/options.png")
execute_process(
  COMMAND ${xvfb} "${RENDER_VIEWS}" "${png}" --size 1200 500 --range 0 10
          --view 0 0 -1 0 1 0 --point-size 5 --scalar-title "distance (units)" --fit 2
          noisy "${WORK_DIR}/noisy.pcd" smoothed "${WORK_DIR}/smooth.pcd" again "${WORK_DIR}/noisy.pcd"
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 300)
xvfb_exit_code(rc "${code_file}")
message("${out}${err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "render_views with options failed with ${rc}")
endif()
file(READ "${png}" dims OFFSET 16 LIMIT 8 HEX)
if(NOT dims STREQUAL "000004b0000001f4")
  message(FATAL_ERROR "${png} is not 1200x500 (IHDR ${dims})")
endif()

# --fit names a view that does not exist: an error, exit code 2, and no picture.
set(png "${WORK_DIR}/badfit.png")
execute_process(
  COMMAND ${xvfb} "${RENDER_VIEWS}" "${png}" --fit 3 noisy "${WORK_DIR}/noisy.pcd"
          smoothed "${WORK_DIR}/smooth.pcd"
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 300)
xvfb_exit_code(rc "${code_file}")
if(NOT rc EQUAL 2 OR NOT err MATCHES "--fit" OR EXISTS "${png}")
  message(FATAL_ERROR "render_views --fit 3 with two views: rc ${rc}, ${err}")
endif()

# A missing input file: an error, exit code 2, and no picture.
set(png "${WORK_DIR}/missing.png")
execute_process(
  COMMAND ${xvfb} "${RENDER_VIEWS}" "${png}" noisy "${WORK_DIR}/noisy.pcd"
          absent "${WORK_DIR}/does_not_exist.pcd"
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 300)
xvfb_exit_code(rc "${code_file}")
message("${out}${err}")
if(NOT rc EQUAL 2)
  message(FATAL_ERROR "render_views with a missing input returned ${rc}, expected 2")
endif()
if(NOT err MATCHES "does_not_exist.pcd: no such file")
  message(FATAL_ERROR "render_views did not name the missing input")
endif()
if(EXISTS "${png}" OR EXISTS "${png}.partial.png")
  message(FATAL_ERROR "render_views wrote ${png} although an input was missing")
endif()
