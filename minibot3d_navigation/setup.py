# Installs the Python package src/minibot3d_navigation (the wanderer) for catkin_python_setup(); do
# not run it directly.
from catkin_pkg.python_setup import generate_distutils_setup
from setuptools import setup

setup(**generate_distutils_setup(packages=['minibot3d_navigation'], package_dir={'': 'src'}))
