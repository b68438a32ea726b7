"""minibot3d_navigation's Python side: the trajectory-planner tuning tool (tuning/)."""
