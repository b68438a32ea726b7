"""minibot3d_navigation's Python side: the wanderer (wanderer.py) that simple_navi_goals.py and
the global-localization tools drive with while amcl has no fix yet."""
