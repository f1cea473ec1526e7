#!/usr/bin/env bash
# One idempotent set-up: virtual environment with pinned ROS 2 Kilted wheels, the fixes of
# DESIGN.md §2, and a colcon build of the workspace into ros2_ws/. Called by ./hawt; a run with
# nothing changed only compares two stamps. Fails loudly, naming the step and what is missing.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
VENV="$ROOT/.venv"
WS="$ROOT/ros2_ws"
PY="${HAWT_PYTHON:-python3.11}"

fail() { echo "hawt setup: $*" >&2; exit 1; }
say() { [ -n "${HAWT_QUIET_SETUP:-}" ] || echo "hawt setup: $*" >&2; }

# Hash of the files a step depends on; a step reruns only when its hash changes.
digest() { (cd "$ROOT" && sha256sum "$@" | sha256sum | cut -c1-16); }

check_tools() {
  command -v "$PY" >/dev/null || fail "no $PY on PATH (the ROS 2 Kilted wheels are built for CPython 3.11)"
  command -v cmake >/dev/null || fail "no cmake on PATH (needed to build hawt_msgs); install it with: apt-get install cmake"
  command -v g++ >/dev/null || fail "no g++ on PATH (needed to build hawt_msgs); install it with: apt-get install g++"
}

install_python_packages() {
  local want have=""
  want="$(digest requirements.txt requirements-lock.txt)"
  [ -f "$VENV/.hawt-requirements" ] && have="$(cat "$VENV/.hawt-requirements")"
  [ "$want" = "$have" ] && return 0
  check_tools
  if [ ! -x "$VENV/bin/python" ]; then
    say "creating the virtual environment in .venv"
    "$PY" -m venv "$VENV" || fail "could not create the virtual environment with $PY -m venv"
  fi
  say "installing pinned packages (requirements.txt, constrained by requirements-lock.txt)"
  "$VENV/bin/python" -m pip install --quiet --disable-pip-version-check \
      -r "$ROOT/requirements.txt" -c "$ROOT/requirements-lock.txt" 2> >(grep -v "is ignored: it is neither" >&2) \
    || fail "pip could not install requirements.txt (see the pip error above)"
  rewrite_wheel_cmake_paths
  echo "$want" > "$VENV/.hawt-requirements"
}

install_nodeps_packages() {
  local want have=""
  want="$(digest requirements-nodeps.txt)"
  [ -f "$VENV/.hawt-nodeps" ] && have="$(cat "$VENV/.hawt-nodeps")"
  [ "$want" = "$have" ] && return 0
  say "installing requirements-nodeps.txt without dependencies (rosco's controller library, wisdem's CCBlade)"
  "$VENV/bin/python" -m pip install --quiet --disable-pip-version-check --no-deps -r "$ROOT/requirements-nodeps.txt" \
      2> >(grep -v "is ignored: it is neither" >&2) || fail "pip could not install requirements-nodeps.txt (see the pip error above)"
  echo "$want" > "$VENV/.hawt-nodeps"
}

# The wheels' CMake export files name the wheel builder's include dirs (DESIGN.md §2);
# point them at this interpreter's Python and numpy headers so rosidl's Python generator builds.
rewrite_wheel_cmake_paths() {
  local py_inc np_inc
  py_inc="$("$VENV/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["include"])')"
  np_inc="$("$VENV/bin/python" -c 'import numpy; print(numpy.get_include())')"
  [ -f "$py_inc/Python.h" ] || fail "no Python.h in $py_inc: install the Python 3.11 development headers"
  { grep -rl --include='*.cmake' '/opt/python/cp311-cp311' "$VENV/share" || true; } | while read -r f; do
    sed -i "s#/opt/python/cp311-cp311/include/python3.11#$py_inc#g;
            s#/opt/python/cp311-cp311/lib/python3.11/site-packages/numpy/_core/include#$np_inc#g" "$f"
  done
}

# Python packages are installed as links to their sources (--symlink-install), so only build
# files, interface definitions and data decide whether colcon has to run again.
workspace_files() {
  (cd "$ROOT" && find "${PACKAGES[@]}" -type f \
     \( -name '*.msg' -o -name '*.srv' -o -name 'CMakeLists.txt' -o -name 'package.xml' \
        -o -name 'setup.py' -o -name 'setup.cfg' -o -path '*/resource/*' -o -path '*/launch/*' \
        -o -path '*/config/*' \) | sort)
}

build_workspace() {
  local want have=""
  want="$(digest $WORKSPACE_FILES)"
  [ -f "$WS/.hawt-build" ] && have="$(cat "$WS/.hawt-build")"
  [ "$want" = "$have" ] && [ -d "$WS/install" ] && return 0
  check_tools
  say "building the workspace with colcon (ros2_ws/)"
  (
    cd "$ROOT"
    export PATH="$VENV/bin:$PATH" AMENT_PREFIX_PATH="$VENV" CMAKE_PREFIX_PATH="$VENV"
    unset COLCON_PREFIX_PATH
    "$VENV/bin/colcon" --log-base "$WS/log" build --base-paths "${PACKAGES[@]}" \
        --build-base "$WS/build" --install-base "$WS/install" --symlink-install \
        --event-handlers console_cohesion- summary- status- \
        --cmake-args -DPython3_EXECUTABLE="$VENV/bin/python" -DBUILD_TESTING=OFF \
      > "$WS/build.log" 2>&1
  ) || { tail -n 40 "$WS/build.log" >&2; fail "colcon build failed (full log: ros2_ws/build.log)"; }
  echo "$want" > "$WS/.hawt-build"
}

# libhawt_discon.so, the DISCON library whose controller is a hawt graph (issue 33), built with the
# machine's C compiler into ros2_ws/lib; its stamp is the source's digest, which hawt_tools.discon_bridge
# checks before it names the library, so a library older than its source is never used.
DISCON_SOURCE="hawt_tools/discon_bridge/hawt_discon.c"
DISCON_LIB="$WS/lib/libhawt_discon.so"
build_discon_bridge() {
  local want have="" source="$DISCON_SOURCE" lib="$DISCON_LIB" cc="${CC:-cc}"
  want="$(digest "$source")"
  [ -f "$WS/lib/.hawt-discon" ] && have="$(cat "$WS/lib/.hawt-discon")"
  [ "$want" = "$have" ] && [ -f "$lib" ] && return 0
  command -v "$cc" >/dev/null || fail "no C compiler $cc on PATH (needed for libhawt_discon.so); install one with: apt-get install gcc"
  say "building libhawt_discon.so with $cc (ros2_ws/lib/)"
  mkdir -p "$WS/lib"
  rm -f "$lib" "$WS/lib/.hawt-discon"
  "$cc" -O2 -fPIC -shared -Wall -Wextra -Werror -o "$lib.tmp" "$ROOT/$source" -lm > "$WS/lib/discon-build.log" 2>&1 \
    || { local code=$?; fail "$cc could not build libhawt_discon.so from $source: $(grep -m1 -i error "$WS/lib/discon-build.log" || echo "exit status $code") (full log: ros2_ws/lib/discon-build.log)"; }
  mv "$lib.tmp" "$lib"
  echo "$want" > "$WS/lib/.hawt-discon"
}

# The plant's compiled kernels (numba, hawt_plant/compiled.py): compiled once into a cache folder keyed by the
# content of hawt_plant's sources, just in time into numba's cache and ahead of time into an extension module
# (hawt_plant/kernel_export.py), so that no run pays for compiling or for importing numba, and no run uses code older
# than its source.
# The folder's key is a hash of the sources' content (hawt_plant.kernel_cache); asking Python for it costs a tenth of a
# second, so the answer is kept beside the sources' sizes, inodes and times and asked again when one of them changes.
# (A run finds its folder by the content itself, so a change this misses costs a compile on first use, never stale
# kernels.)
compile_plant_kernels() {
  local folder sources memo="$WS/.hawt-kernels"
  local python=("env" "PYTHONPATH=$ROOT/hawt_plant:$ROOT/hawt_core" "$VENV/bin/python")
  sources="${NUMBA_CACHE_DIR:-}|${XDG_CACHE_HOME:-}|$HOME|$(stat -c '%n %s %i %.9Y' "$ROOT"/hawt_plant/hawt_plant/*.py)"
  if [ -f "$memo" ] && [ "$(head -n -1 "$memo")" = "$sources" ]; then
    folder="$(tail -n 1 "$memo")"
    [ -f "$folder/.hawt-complete" ] && return 0
  fi
  folder="$("${python[@]}" -m hawt_plant.kernel_cache)" \
    || fail "could not find the folder of the plant's kernels (see the error above)"
  printf '%s\n%s\n' "$sources" "$folder" > "$memo"
  [ -f "$folder/.hawt-complete" ] && return 0
  say "compiling the plant's kernels with numba, about a minute (once per change of hawt_plant's sources, into $folder)"
  mkdir -p "$folder"
  "${python[@]}" -m hawt_plant.kernel_export > "$folder/compile.log" 2>&1 \
    || fail "numba could not compile the plant's kernels: $(grep -m1 -iE 'error|exception' "$folder/compile.log" || echo "see $folder/compile.log") (full log: $folder/compile.log)"
  touch "$folder/.hawt-complete"
}

# What the steps above read, in one digest (with the settings that choose the kernels' folder): a run with nothing changed
# compares it with the one kept when the steps last completed and stops there, if what they made is still there. Each
# step's own check costs a few processes; together they took a tenth of a second of every ./hawt command.
everything_read() {
  printf '%s|%s|%s|' "${NUMBA_CACHE_DIR:-}" "${XDG_CACHE_HOME:-}" "$HOME"
  (cd "$ROOT" && sha256sum requirements.txt requirements-lock.txt requirements-nodeps.txt "$DISCON_SOURCE" \
     hawt_plant/hawt_plant/*.py $WORKSPACE_FILES | sha256sum | cut -c1-16)
}

everything_made() {
  local memo=()
  [ -x "$VENV/bin/python" ] && [ -d "$WS/install" ] && [ -f "$DISCON_LIB" ] && [ -f "$WS/.hawt-kernels" ] || return 1
  mapfile -t memo < "$WS/.hawt-kernels"
  [ -f "${memo[-1]}/.hawt-complete" ]
}

mkdir -p "$WS"
# Every top-level folder with a package.xml is a package of the workspace.
PACKAGES=()
for manifest in "$ROOT"/*/package.xml; do
  manifest="${manifest%/package.xml}"
  PACKAGES+=("${manifest##*/}")
done
WORKSPACE_FILES="$(workspace_files)"
read_now="$(everything_read)"
if [ -f "$WS/.hawt-setup" ] && [ "$(< "$WS/.hawt-setup")" = "$read_now" ] && everything_made; then
  exit 0
fi
install_python_packages
install_nodeps_packages
build_workspace
build_discon_bridge
compile_plant_kernels
echo "$read_now" > "$WS/.hawt-setup"
