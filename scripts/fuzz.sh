#!/usr/bin/env bash
# Fuzzes the scene parser with libFuzzer (tests/fuzz) for a bounded time, FUZZ_SECONDS (default 120): builds
# build/fuzz with clang, AddressSanitizer and UBSan, then mutates the seed corpus and the kept regressions.
# Exits non-zero if the fuzzer finds a crash, hang, leak, huge allocation or sanitizer report, and says where
# the input that caused it was saved. New corpus entries go to build/fuzz/corpus, never into the repository.
set -euo pipefail
cd "$(dirname "$0")/.."
root="$(pwd)"

bash scripts/setup.sh
# libFuzzer comes with Debian's clang: the compiler, and libclang-rt-dev's runtimes (libclang_rt.fuzzer*.a).
fuzz_packages=(clang libclang-rt-dev)
installed="$(dpkg-query -W -f='${Status}\n' "${fuzz_packages[@]}" 2>/dev/null | grep -c "install ok installed" || true)"
if [ "$installed" -ne ${#fuzz_packages[@]} ]; then
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  echo "fuzz: installing ${fuzz_packages[*]}"
  $sudo apt-get update
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y --no-install-recommends "${fuzz_packages[@]}"
fi

build="$root/build/fuzz"
cmake -S "$root" -B "$build" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DFIRN_BUILD_FUZZERS=ON -DFIRN_BUILD_TESTS=OFF
cmake --build "$build" --target firn_scene_fuzzer --parallel "$(nproc)"

# The first corpus folder is the one libFuzzer adds to; the repository's folders after it are only read.
mkdir -p "$build/corpus"
artifacts="$build/artifacts/$(date +%Y%m%d-%H%M%S)"
mkdir -p "$artifacts"
seconds="${FUZZ_SECONDS:-120}"
echo "fuzz: fuzzing the scene parser for ${seconds} s"
status=0
"$build/tests/fuzz/firn_scene_fuzzer" "$build/corpus" "$root/tests/fuzz/corpus" "$root/tests/fuzz/regressions" \
  -dict="$root/tests/fuzz/scene.dict" -max_len=4096 -timeout=5 -rss_limit_mb=2048 \
  -max_total_time="$seconds" -artifact_prefix="$artifacts/" -print_final_stats=1 || status=$?
if [ "$status" -ne 0 ]; then
  echo "fuzz: the fuzzer found a defect (exit status $status); the input that triggers it:" >&2
  find "$artifacts" -type f -printf '  %p\n' >&2
  echo "fuzz: reproduce with $build/tests/fuzz/firn_scene_fuzzer FILE; shrink it with -minimize_crash=1 -runs=10000;" \
       "once fixed, keep it in tests/fuzz/regressions/" >&2
  exit "$status"
fi
rmdir "$artifacts"
echo "fuzz: no defect found in ${seconds} s"
