# Environment of the built workspace; sourced by ./hawt (not meant to be run on its own).
# Puts the virtual environment and the colcon install space on the paths, and sets what the
# ROS 2 wheels' bootstrapper would otherwise set by re-executing every Python process.
HAWT_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
export PATH="$HAWT_ROOT/.venv/bin:$PATH"
export COLCON_PYTHON_EXECUTABLE="$HAWT_ROOT/.venv/bin/python"
# shellcheck disable=SC1091
source "$HAWT_ROOT/ros2_ws/install/setup.bash"
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
unset _hawt_site _hawt_libs
