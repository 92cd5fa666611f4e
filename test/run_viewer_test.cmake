# pcl_graph_denoise_viewer, run as a user runs it.
#   MODE=png:    the demo's noisy scene and its result (outliers removed: compared with
#                the nearest input point), and the CLI's result of the same scene with
#                the outliers kept as NaN (compared by index, NaN points skipped), each
#                rendered headless under xvfb-run into a PNG that must exist, be a PNG of
#                the size asked, and show points in both views.
#   MODE=errors: -h, an invalid option, a missing input, a blank view and no X
#                display: the exit codes, one-line errors, and no PNG left behind.
#   cmake -DMODE=png|errors -DVIEWER=<exe> [-DDEMO=<exe> -DCLI=<exe>] -DWORK_DIR=<dir>
#         -P run_viewer_test.cmake
if(NOT VIEWER OR NOT WORK_DIR OR NOT MODE MATCHES "^(png|errors)$")
  message(FATAL_ERROR "usage: cmake -DMODE=png|errors -DVIEWER=<exe> [-DDEMO=<exe> -DCLI=<exe>] "
                      "-DWORK_DIR=<dir> -P run_viewer_test.cmake")
endif()
find_program(XVFB_RUN xvfb-run)
if(NOT XVFB_RUN)
  message(FATAL_ERROR "xvfb-run not found: the viewer needs an X server (apt-get install xvfb xauth)")
endif()
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")
include("${CMAKE_CURRENT_LIST_DIR}/xvfb.cmake")
xvfb_launcher(xvfb "${WORK_DIR}/exit_code")

# A run that renders loads Mesa's GL driver with dlopen and unloads it at exit, which
# leaves allocations LeakSanitizer cannot attribute (reported in whatever library is
# mapped there next): in the sanitizer build (scripts/test_sanitizers.sh) such runs are
# checked for every error but leaks. Runs that fail before rendering keep the leak check.
set(leak_check_off "detect_leaks=0")
if(DEFINED ENV{ASAN_OPTIONS} AND NOT "$ENV{ASAN_OPTIONS}" STREQUAL "")
  set(leak_check_off "$ENV{ASAN_OPTIONS}:detect_leaks=0")
endif()

# run_viewer(EXPECTED_EXIT STDERR_REGEX [NO_DISPLAY|RENDERS] args...): runs the viewer
# (under xvfb-run, or with DISPLAY unset) and fails unless it exits with EXPECTED_EXIT and
# its stderr matches STDERR_REGEX; when it fails, the PNG after -png must not exist. Sets
# out and err.
function(run_viewer expected pattern)
  set(args ${ARGN})
  set(launcher ${xvfb})
  if(args AND args MATCHES "^NO_DISPLAY")
    list(POP_FRONT args)
    set(launcher ${CMAKE_COMMAND} -E env --unset=DISPLAY)
  elseif(args AND args MATCHES "^RENDERS")
    list(POP_FRONT args)
    set(launcher ${CMAKE_COMMAND} -E env "ASAN_OPTIONS=${leak_check_off}" ${launcher})
  endif()
  execute_process(COMMAND ${launcher} "${VIEWER}" ${args}
    RESULT_VARIABLE code OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr TIMEOUT 240)
  xvfb_exit_code(code "${WORK_DIR}/exit_code")
  string(JOIN " " command ${args})
  message("viewer ${command}: exit ${code}\n${stdout}${stderr}")
  if(NOT code EQUAL expected OR NOT stderr MATCHES "${pattern}")
    message(FATAL_ERROR "expected exit code ${expected} and stderr matching '${pattern}'")
  endif()
  list(FIND args -png at)
  if(NOT expected EQUAL 0 AND at GREATER_EQUAL 0)
    math(EXPR at "${at} + 1")
    list(GET args ${at} png)
    if(EXISTS "${png}" OR EXISTS "${png}.partial.png")
      message(FATAL_ERROR "the viewer failed but left ${png} behind")
    endif()
  endif()
  set(out "${stdout}" PARENT_SCOPE)
  set(err "${stderr}" PARENT_SCOPE)
endfunction()

# Fails unless `png` exists, is a PNG of width x height, and the viewer reported more
# than 0.5% of non-background pixels in both views (its own check passed too).
function(check_picture png width height)
  if(NOT EXISTS "${png}" OR EXISTS "${png}.partial.png")
    message(FATAL_ERROR "the viewer did not write ${png} (or left its temporary file)")
  endif()
  file(READ "${png}" signature LIMIT 8 HEX)
  file(READ "${png}" ihdr OFFSET 16 LIMIT 8 HEX)  # IHDR width and height, big-endian
  string(SUBSTRING "${ihdr}" 0 8 png_w)
  string(SUBSTRING "${ihdr}" 8 8 png_h)
  math(EXPR png_w "0x${png_w}")
  math(EXPR png_h "0x${png_h}")
  if(NOT signature STREQUAL "89504e470d0a1a0a" OR NOT png_w EQUAL width OR NOT png_h EQUAL height)
    message(FATAL_ERROR "${png} is not a ${width}x${height} PNG (signature ${signature}, IHDR ${ihdr})")
  endif()
  file(SIZE "${png}" size)
  if(size LESS 20000)
    message(FATAL_ERROR "${png} is only ${size} bytes: blank picture?")
  endif()
  if(NOT out MATCHES "${png} ${width}x${height}, non-background pixels: ([0-9.e+-]+)% \\(input\\), ([0-9.e+-]+)% \\(result\\)")
    message(FATAL_ERROR "the viewer did not report the path and the coverage of both views")
  endif()
  if(NOT CMAKE_MATCH_1 GREATER 0.5 OR NOT CMAKE_MATCH_2 GREATER 0.5)
    message(FATAL_ERROR "a view is (nearly) blank: ${CMAKE_MATCH_1}% input, ${CMAKE_MATCH_2}% result")
  endif()
endfunction()

if(MODE STREQUAL "png")
  if(NOT DEMO OR NOT CLI)
    message(FATAL_ERROR "MODE=png needs -DDEMO=<pcl_graph_denoise_demo> and -DCLI=<pcl_graph_denoise>")
  endif()
  set(noisy "${WORK_DIR}/demo_input.pcd")
  set(organized "${WORK_DIR}/organized.pcd")
  execute_process(COMMAND "${DEMO}" "${WORK_DIR}" COMMAND_ERROR_IS_FATAL ANY OUTPUT_QUIET)
  execute_process(COMMAND "${CLI}" "${noisy}" "${organized}" -q -outliers -keep_organized 1 -tv
    COMMAND_ERROR_IS_FATAL ANY)

  # Outliers removed: fewer points, each compared with the nearest input point.
  run_viewer(0 " 0 result points compared by index, [1-9][0-9]* with the nearest input point"
             RENDERS "${noisy}" "${WORK_DIR}/demo_output.pcd" -png "${WORK_DIR}/removed.png")
  check_picture("${WORK_DIR}/removed.png" 1600 800)

  # Outliers kept as NaN: same size, compared by index, the NaN points skipped.
  run_viewer(0 "[1-9][0-9]* result points compared by index, 0 with the nearest input point; moved: median"
             RENDERS "${noisy}" "${organized}" -png "${WORK_DIR}/organized.png" -size 1000 500)
  check_picture("${WORK_DIR}/organized.png" 1000 500)

  # By depth, with every option.
  run_viewer(0 "" RENDERS "${noisy}" "${organized}" -color depth -png "${WORK_DIR}/depth.png" -size 900 600
             -view -1 -2 -1.5 0 0 1 -fit both -point_size 3 -range 0 0.3)
  check_picture("${WORK_DIR}/depth.png" 900 600)
else()
  # -h: the usage on stdout, exit code 0.
  run_viewer(0 "^$" -h)
  if(NOT out MATCHES "Usage: pcl_graph_denoise_viewer input" OR NOT out MATCHES "-png OUT.png")
    message(FATAL_ERROR "-h did not print the usage")
  endif()

  # Two tiny clouds for the cases below (a NaN point in the first), the second far away.
  set(cloud "${WORK_DIR}/small.pcd")
  set(far "${WORK_DIR}/far.pcd")
  foreach(file_points IN ITEMS "${cloud}|0 0 1\n1 0 1\nnan nan nan\n" "${far}|1000 0 1\n1001 0 1\n")
    string(REPLACE "|" ";" file_points "${file_points}")
    list(GET file_points 0 path)
    list(GET file_points 1 points)
    string(REGEX MATCHALL "\n" lines "${points}")
    list(LENGTH lines n)
    file(WRITE "${path}" "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
      "WIDTH ${n}\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS ${n}\nDATA ascii\n${points}")
  endforeach()

  # An invalid option value: exit code 2, a one-line error naming it, no picture.
  run_viewer(2 "error: invalid value 'rainbow' for -color"
             "${cloud}" "${cloud}" -color rainbow -png "${WORK_DIR}/bad_option.png")
  # A missing input: exit code 1, the file named, no picture.
  run_viewer(1 "does_not_exist.pcd: no such file"
             "${WORK_DIR}/does_not_exist.pcd" "${cloud}" -png "${WORK_DIR}/missing.png")
  # A result far from the input: the camera frames the result, the input's view stays
  # blank, the check fails: exit code 1, the view named, no picture kept.
  run_viewer(1 "view 1 \\(.*small.pcd\\) has 0 non-background pixels"
             RENDERS "${cloud}" "${far}" -png "${WORK_DIR}/blank.png")
  # No X display: exit code 1, a hint to use xvfb-run, no picture.
  run_viewer(1 "no X display.*xvfb-run" NO_DISPLAY "${cloud}" "${cloud}" -png "${WORK_DIR}/no_display.png")
endif()
