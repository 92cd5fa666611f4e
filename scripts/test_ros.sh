#!/usr/bin/env bash
# ROS 1 with Debian 12's own packages: installs what the project and the ROS node need
# (as root; only what is missing), builds the library and
# examples/ros/pcl_graph_denoise_ros with catkin_make_isolated in a catkin workspace in
# ./build-ros/ws (whose src/ links to this clone and to the node), and runs the node's
# rostest (test/denoise.test): noisy clouds through five configurations of the node,
# bad clouds and bad parameters. Exits non-zero on any failure.
#
# rostest starts its own ROS master on a free port chosen by the system (never the
# default 11311, so a running roscore is neither used nor disturbed) and stops it with
# the nodes; whatever this run started is killed on exit, also on failure or Ctrl-C.
# PGD_ROS_JOBS sets the build jobs (default 2).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)

ros_packages=(catkin libroscpp-dev libsensor-msgs-dev libpcl-conversions-dev
  python3-rospy python3-sensor-msgs python3-rosgraph-msgs python3-roslaunch
  python3-rostest rosbash)
bash scripts/setup.sh --install-only "${ros_packages[@]}"

# Debian's ROS tools and Python modules belong to /usr/bin/python3: a python3 found
# first on PATH (pyenv, a virtualenv) would break catkin and the test client.
export PATH="/usr/bin:$PATH"

ws="$root/build-ros/ws"
echo "== catkin workspace $ws"
mkdir -p "$ws/src"
ln -sfn "$root" "$ws/src/pcl_graph_denoise"
ln -sfn "$root/examples/ros/pcl_graph_denoise_ros" "$ws/src/pcl_graph_denoise_ros"

echo "== catkin_make_isolated (Release, ${PGD_ROS_JOBS:-2} jobs): pcl_graph_denoise, pcl_graph_denoise_ros"
(cd "$ws" && catkin_make_isolated -j"${PGD_ROS_JOBS:-2}" --cmake-args \
  -DCMAKE_BUILD_TYPE=Release -DPYTHON_EXECUTABLE=/usr/bin/python3 \
  -DPCL_GRAPH_DENOISE_BUILD_TESTS=OFF -DPCL_GRAPH_DENOISE_BUILD_EXAMPLES=OFF \
  -DPCL_GRAPH_DENOISE_BUILD_BENCHMARKS=OFF -DPCL_GRAPH_DENOISE_BUILD_TOOLS=OFF) \
  >"$root/build-ros/catkin_make_isolated.log" 2>&1 || {
  tail -n 60 "$root/build-ros/catkin_make_isolated.log"
  echo "error: catkin_make_isolated failed (whole log: build-ros/catkin_make_isolated.log)" >&2
  exit 1
}
grep -E "^(==> Processing|<== Finished)" "$root/build-ros/catkin_make_isolated.log" || true

set +u  # catkin's setup scripts read unset variables
# shellcheck disable=SC1091
source "$ws/devel_isolated/setup.bash"
set -u

# Logs and test results of this run stay in build-ros/; all traffic on the loopback.
export ROS_HOME="$root/build-ros/ros_home"
export ROS_IP=127.0.0.1
unset ROS_HOSTNAME
results="$ROS_HOME/test_results/pcl_graph_denoise_ros"
rm -rf "$results"

# Every process of the test (rostest with its master, rosout, the nodes, the client and
# the nodes it starts) carries this marker in its environment: on exit, whatever still
# has it is killed, by process id.
marker="pgd-ros-test-$$-$(date +%s%N)"
marked() {
  local pid
  for pid in /proc/[0-9]*; do
    pid=${pid#/proc/}
    [ "$pid" != "$$" ] || continue
    tr '\0' '\n' 2>/dev/null <"/proc/$pid/environ" | grep -qx "PGD_ROS_TEST_RUN=$marker" &&
      echo "$pid"
  done
  return 0
}
cleanup() {
  local left _
  left=$(marked) || true
  [ -n "$left" ] || return 0
  echo "== stopping the processes left by the test:" "${left//$'\n'/ }"
  # shellcheck disable=SC2086
  kill -TERM $left 2>/dev/null || true
  sleep 2
  # Again until none is left: one may have started another meanwhile.
  for _ in 1 2 3 4 5; do
    left=$(marked) || true
    [ -n "$left" ] || return 0
    # shellcheck disable=SC2086
    kill -KILL $left 2>/dev/null || true
    sleep 0.5
  done
}
trap cleanup EXIT
trap 'exit 130' INT TERM

echo "== rostest pcl_graph_denoise_ros denoise.test"
echo "   (the ERROR and WARN lines are the bad clouds and the empty result the test provokes)"
status=0
# In the background, so that a signal to this script is handled at once.
PGD_ROS_TEST_RUN="$marker" timeout -s INT -k 30 180 \
  rostest pcl_graph_denoise_ros denoise.test &
wait $! || status=$?

# The plain count of the test cases, from rostest's JUnit file.
summary=$(/usr/bin/python3 - "$results" <<'EOF' || true
import glob, sys
import xml.etree.ElementTree as ET
tests = failed = 0
for path in glob.glob(sys.argv[1] + "/rosunit-*.xml"):
    suite = ET.parse(path).getroot()
    tests += int(suite.get("tests", 0))
    failed += int(suite.get("failures", 0)) + int(suite.get("errors", 0))
print(tests - failed, failed) if tests else None
EOF
)
if [ -z "$summary" ]; then
  echo "error: rostest produced no result (exit status $status); logs in build-ros/ros_home/log" >&2
  exit 1
fi
read -r passed failed <<<"$summary"
echo "ros: $passed passed, $failed failed"
if [ "$status" -ne 0 ] || [ "$failed" -ne 0 ]; then
  echo "error: the ROS test failed (rostest exit status $status); logs in build-ros/ros_home/log" >&2
  exit 1
fi
