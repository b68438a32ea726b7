"""tune_planner: sweeps or optimises move_base parameters over full simulated navigation runs.

Modules, from the bottom up:
  params     the parameter grid, name checking against move_base, per-trial YAML files (no ROS)
  metrics    per-trial figures from a ground-truth trajectory and the world's map (no ROS)
  processes  one headless stack per trial on its own ROS master port; clean process-group kills
  driver     the in-trial ROS client (run as a subprocess, a lock-step participant): sends the
             goals, records the true trajectory
  study      trials, results.csv (atomic, resumable), the grid runner and the Optuna search
  report     the Markdown table and the PNG plots
  cli        `rosrun minibot3d_tuning tune_planner`
"""

# The driver's node name: the stack lists it in lockstep_participants (study), the driver takes it.
DRIVER_NODE = 'tune_planner_driver'
