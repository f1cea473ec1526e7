# Environment of the built workspace; sourced by ./hawt (not meant to be run on its own).
# Puts the virtual environment and the colcon install space on the paths, and sets what the
# ROS 2 wheels' bootstrapper would otherwise set by re-executing every Python process.
HAWT_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
export PATH="$HAWT_ROOT/.venv/bin:$PATH"
export COLCON_PYTHON_EXECUTABLE="$HAWT_ROOT/.venv/bin/python"
# colcon's setup.bash asks a Python process for its paths (a tenth of a second of every ./hawt command): what it sets is
# kept, keyed by the build and the values it reads, and sourced instead while they stay the same.
_hawt_paths=(AMENT_PREFIX_PATH CMAKE_PREFIX_PATH COLCON_PREFIX_PATH LD_LIBRARY_PATH PYTHONPATH)
_hawt_key="$(cat "$HAWT_ROOT/ros2_ws/.hawt-build" 2>/dev/null)|${COLCON_TRACE:-}|$HAWT_ROOT"
for _hawt_name in "${_hawt_paths[@]}"; do _hawt_key+="|${!_hawt_name:-}"; done
_hawt_memo="$HAWT_ROOT/ros2_ws/.hawt-environment"
if [ -f "$_hawt_memo" ] && [ "$(head -n 1 "$_hawt_memo")" = "# $_hawt_key" ]; then
  # shellcheck disable=SC1090
  source "$_hawt_memo"
else
  # shellcheck disable=SC1091
  source "$HAWT_ROOT/ros2_ws/install/setup.bash"
  { echo "# $_hawt_key"
    for _hawt_name in "${_hawt_paths[@]}"; do
      if [ -n "${!_hawt_name+set}" ]; then printf 'export %s=%q\n' "$_hawt_name" "${!_hawt_name}"; fi
    done
  } > "$_hawt_memo.$$" && mv "$_hawt_memo.$$" "$_hawt_memo"
fi
export AMENT_PREFIX_PATH="$AMENT_PREFIX_PATH:$HAWT_ROOT/.venv"
_hawt_site="$HAWT_ROOT/.venv/lib/python3.11/site-packages"
for _hawt_libs in "$HAWT_ROOT/.venv/lib" "$_hawt_site"/ros_*.libs; do
  case ":${LD_LIBRARY_PATH:-}:" in *":$_hawt_libs:"*) ;; *) LD_LIBRARY_PATH="$_hawt_libs:${LD_LIBRARY_PATH:-}" ;; esac
done
export LD_LIBRARY_PATH _ROS_WHEELS_BOOTSTRAP_COMPLETE=1
export RMW_IMPLEMENTATION="${RMW_IMPLEMENTATION:-rmw_fastrtps_cpp}"
# Reliable writers ask for acknowledgements every 0.1 s, not 3 s: a node's stop waits for them (see the file).
export FASTDDS_DEFAULT_PROFILES_FILE="${FASTDDS_DEFAULT_PROFILES_FILE:-$HAWT_ROOT/hawt_node/fastdds_profile.xml}"
# No traffic beyond this machine unless the user asks for it.
export ROS_AUTOMATIC_DISCOVERY_RANGE="${ROS_AUTOMATIC_DISCOVERY_RANGE:-LOCALHOST}"
export PYTHONUNBUFFERED=1
unset _hawt_site _hawt_libs _hawt_paths _hawt_key _hawt_name _hawt_memo
