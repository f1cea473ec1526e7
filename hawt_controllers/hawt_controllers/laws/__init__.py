"""Control laws and the math they run on: plain numpy/scipy, no plant, no ROS."""
