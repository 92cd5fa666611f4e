# evaluation_page_is_the_reports_text: docs/evaluation.md is what scripts/evaluation_report.sh
# writes, so that `bash scripts/evaluate.sh` regenerates the page rather than erasing the
# text added to it by hand. The script runs on a results folder whose measured tables are
# markers (and whose PU-GAN data gives the sizes and options the page's command line names),
# with gnuplot and xvfb-run stubbed out; the page must then be the script's text with each
# marker standing for a non-empty table. A paragraph edited on the page only fails here:
# put it into the script's text.
#   cmake -DSOURCE_DIR=... -DWORK_DIR=... -P run_evaluation_report_test.cmake
cmake_minimum_required(VERSION 3.18)
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}/scripts" "${WORK_DIR}/docs" "${WORK_DIR}/results"
     "${WORK_DIR}/bin")
file(COPY "${SOURCE_DIR}/scripts/evaluation_report.sh" DESTINATION "${WORK_DIR}/scripts")
foreach(tool gnuplot xvfb-run)
  file(WRITE "${WORK_DIR}/bin/${tool}" "#!/bin/sh\nexit 0\n")
  file(CHMOD "${WORK_DIR}/bin/${tool}" PERMISSIONS OWNER_READ OWNER_WRITE OWNER_EXECUTE)
endforeach()

# The measured tables the script copies in (cat "$results/NAME.md"), as markers.
file(READ "${SOURCE_DIR}/scripts/evaluation_report.sh" script)
string(REGEX MATCHALL "cat \"\\$results/[a-z0-9_]+\\.md\"" tables "${script}")
if(NOT tables)
  message(FATAL_ERROR "scripts/evaluation_report.sh copies no table from its results folder")
endif()
foreach(table IN LISTS tables)
  string(REGEX REPLACE ".*/([a-z0-9_]+)\\.md\"" "\\1" name "${table}")
  file(WRITE "${WORK_DIR}/results/${name}.md" "@@table ${name}@@\n")
endforeach()

# The PU-GAN run's sizes and options, as the page names them.
file(READ "${SOURCE_DIR}/docs/evaluation.md" page)
if(NOT page MATCHES "build/bench/evaluate pugan --sizes ([0-9,]+)([^`]*)`")
  message(FATAL_ERROR "docs/evaluation.md names no `build/bench/evaluate pugan --sizes` command")
endif()
string(REPLACE "," ";" sizes "${CMAKE_MATCH_1}")
set(options "${CMAKE_MATCH_2}")
set(dat "")
if(options MATCHES "--two-ring")
  string(APPEND dat "# adaptive_support 0\n")
endif()
set(risk 0.5)
if(options MATCHES "--no-risk")
  set(risk nan)
endif()
foreach(size IN LISTS sizes)
  string(APPEND dat "casting ${size} 1 \"Tikhonov (risk γ)\" ${risk} x\n")
endforeach()
file(WRITE "${WORK_DIR}/results/pugan.dat" "${dat}")

execute_process(
  COMMAND ${CMAKE_COMMAND} -E env "PATH=${WORK_DIR}/bin:$ENV{PATH}"
          bash "${WORK_DIR}/scripts/evaluation_report.sh" "${WORK_DIR}/results"
  RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "scripts/evaluation_report.sh failed (${status}):\n${out}${err}")
endif()
file(READ "${WORK_DIR}/docs/evaluation.md" written)

# The page must be the written text, each marker standing for some non-empty text.
string(REGEX MATCHALL "@@table [a-z0-9_]+@@\n" markers "${written}")
list(LENGTH markers count)
set(rest "${page}")
set(first TRUE)
# The next piece of the script's text (up to `marker`, or to the end for "-") must be on
# the page: at its start for the first piece, after some table's text for the others.
function(expect_piece marker)
  if(marker STREQUAL "-")
    set(piece "${written}")
  else()
    string(FIND "${written}" "${marker}" at)
    string(SUBSTRING "${written}" 0 ${at} piece)
    string(LENGTH "${marker}" marker_length)
    math(EXPR after "${at} + ${marker_length}")
    string(SUBSTRING "${written}" ${after} -1 remaining)
    set(written "${remaining}" PARENT_SCOPE)
  endif()
  string(FIND "${rest}" "${piece}" found)
  if(found EQUAL -1 OR (first AND NOT found EQUAL 0) OR (NOT first AND found EQUAL 0))
    string(REGEX MATCH "^[^\n]*\n?[^\n]*\n?[^\n]*" opening "${piece}")
    message(FATAL_ERROR "docs/evaluation.md is not what scripts/evaluation_report.sh "
            "writes: the script's text\n${opening}\n...\nis not on the page where it belongs "
            "(before ${marker}; - = the end). The script's output with its tables as markers "
            "is ${WORK_DIR}/docs/evaluation.md: diff it against the page and move the page's "
            "hand edits into the script.")
  endif()
  string(LENGTH "${piece}" length)
  math(EXPR after "${found} + ${length}")
  string(SUBSTRING "${rest}" ${after} -1 remaining)
  set(rest "${remaining}" PARENT_SCOPE)
  set(first FALSE PARENT_SCOPE)
endfunction()
foreach(marker IN LISTS markers)
  expect_piece("${marker}")
endforeach()
expect_piece(-)
if(NOT rest STREQUAL "")
  string(SUBSTRING "${rest}" 0 200 opening)
  message(FATAL_ERROR "docs/evaluation.md goes on after the end of what "
          "scripts/evaluation_report.sh writes:\n${opening}")
endif()
message(STATUS "docs/evaluation.md is scripts/evaluation_report.sh's text with ${count} "
        "measured tables")
