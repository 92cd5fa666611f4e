#!/usr/bin/env bash
# libFuzzer on the command line's file reading and on the three filters (fuzz/), built
# with clang, AddressSanitizer and UndefinedBehaviorSanitizer in ./build-fuzz. The
# targets run side by side, each for PGD_FUZZ_SECONDS seconds (default 30) on a copy of
# its seed corpus fuzz/corpus/<target>; a crash, a sanitizer report, a broken invariant,
# a timeout or an out-of-memory fails the run, and the input is left in
# build-fuzz/artifacts/.
# Needs what scripts/setup.sh installs, and clang with its fuzzer runtime (installed here
# with apt-get, as root, when missing).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${PGD_FUZZ_SECONDS:-30}"
bash scripts/setup.sh >/dev/null

# clang and libFuzzer's runtime (libclang-rt-<version>-dev on Debian 12).
fuzzer_works () {
  command -v clang++ >/dev/null 2>&1 || return 1
  local dir; dir="$(mktemp -d)"
  printf '#include <cstddef>\n#include <cstdint>\nextern "C" int LLVMFuzzerTestOneInput (const uint8_t *, size_t) { return 0; }\n' > "$dir/t.cpp"
  clang++ -fsanitize=fuzzer,address,undefined "$dir/t.cpp" -o "$dir/t" >/dev/null 2>&1
  local rc=$?
  rm -rf "$dir"
  return $rc
}
if ! fuzzer_works; then
  if [ "$(id -u)" -ne 0 ]; then
    echo "error: clang with libFuzzer is missing and installing it needs root" >&2
    exit 1
  fi
  export DEBIAN_FRONTEND=noninteractive
  echo "== installing clang"
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends clang >/dev/null
  major="$(clang++ --version | sed -n 's/.*clang version \([0-9]*\).*/\1/p' | head -n 1)"
  fuzzer_works || apt-get install -y -qq --no-install-recommends "libclang-rt-${major}-dev" >/dev/null
  fuzzer_works || { echo "error: clang++ -fsanitize=fuzzer does not link" >&2; exit 1; }
fi

targets=(fuzz_cloud_file fuzz_filters)
flags="-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer -g"
flags+=" -DEIGEN_MALLOC_ALREADY_ALIGNED=1"  # allocate as Debian's PCL does: scripts/test_sanitizers.sh
flags+=" -fsanitize-coverage-ignorelist=$PWD/fuzz/coverage_ignorelist.txt"
echo "== configuring and building the fuzz targets with clang (2 jobs)"
# The filters pre-compiled for pcl::PointXYZ only, the one type the targets use.
cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DPCL_GRAPH_DENOISE_BUILD_TESTS=OFF -DPCL_GRAPH_DENOISE_BUILD_EXAMPLES=OFF \
  -DPCL_GRAPH_DENOISE_BUILD_BENCHMARKS=OFF -DPCL_GRAPH_DENOISE_BUILD_TOOLS=OFF \
  -DPCL_GRAPH_DENOISE_BUILD_FUZZERS=ON -DPCL_GRAPH_DENOISE_POINT_TYPES=pcl::PointXYZ \
  "-DCMAKE_CXX_FLAGS=$flags" "-DCMAKE_C_FLAGS=$flags" \
  "-DCMAKE_EXE_LINKER_FLAGS=-fsanitize=address,undefined" \
  "-DCMAKE_SHARED_LINKER_FLAGS=-fsanitize=address,undefined" >/dev/null
cmake --build build-fuzz --parallel 2 --target "${targets[@]}" >/dev/null

rm -rf build-fuzz/artifacts
mkdir -p build-fuzz/artifacts
# Sanitizer reports go to files too: the tool's reading holds stderr back (StderrCapture),
# and a report printed then would be lost.
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:log_path=$PWD/build-fuzz/artifacts/asan"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:log_path=$PWD/build-fuzz/artifacts/ubsan"
# The targets run at the same time, one per core (libFuzzer runs one job in one thread).
pids=()
for target in "${targets[@]}"; do
  # A fresh copy of the seeds: what the run adds stays out of the repository.
  rm -rf "build-fuzz/corpus/$target"
  mkdir -p "build-fuzz/corpus/$target"
  cp fuzz/corpus/"$target"/* "build-fuzz/corpus/$target/"
  echo "== fuzzing $target for ${seconds} s"
  "build-fuzz/fuzz/$target" "build-fuzz/corpus/$target" -max_total_time="$seconds" \
    -timeout=20 -rss_limit_mb=2048 -max_len=4096 -print_final_stats=1 \
    -artifact_prefix="build-fuzz/artifacts/$target-" >"build-fuzz/$target.log" 2>&1 &
  pids+=($!)
done
failed=0
for index in "${!targets[@]}"; do
  target="${targets[$index]}"
  log="build-fuzz/$target.log"
  if ! wait "${pids[$index]}"; then
    tail -n 60 "$log" >&2
    echo "error: $target failed; the input is in build-fuzz/artifacts/ (full log: $log)" >&2
    failed=1
    continue
  fi
  echo "== $target:"
  grep -E "stat::number_of_executed_units|stat::peak_rss_mb" "$log" | sed "s/^/  /"
done
if [ "$failed" -ne 0 ]; then
  cat build-fuzz/artifacts/asan.* build-fuzz/artifacts/ubsan.* 2>/dev/null | head -n 80 >&2 || true
  exit 1
fi
echo "== fuzzing: no crash"
