# Running a program headless under xvfb-run, for the test scripts that render
# (run_viewer_test.cmake, run_render_views_test.cmake; include()d after they found
# XVFB_RUN). xvfb-run exits with 5 instead of the program's own code when it fails to
# clean up its temporary directory afterwards (seen once in CI, with two such tests at
# the same time): the launcher writes the program's code to a file, and xvfb_exit_code
# reads it back.

# xvfb_launcher(<var> <code_file>): the command prefix, to be followed by the program and
# its arguments. The shell script is one argument with newlines between its commands
# (a CMake list splits on semicolons).
function(xvfb_launcher var code_file)
  set(${var} ${XVFB_RUN} -a -s "-screen 0 1920x1080x24"
      sh -c "code_file=$1\nshift\n\"$@\"\ncode=$?\necho $code > \"$code_file\"\nexit $code"
      sh "${code_file}" PARENT_SCOPE)
endfunction()

# xvfb_exit_code(<rc_var> <code_file>): after execute_process, sets <rc_var> to the
# program's own exit code when it was recorded (and forgets the record).
function(xvfb_exit_code rc_var code_file)
  if(EXISTS "${code_file}")
    file(STRINGS "${code_file}" code LIMIT_COUNT 1)
    file(REMOVE "${code_file}")
    set(${rc_var} "${code}" PARENT_SCOPE)
  endif()
endfunction()
