# Installs the Python module (src/minibot3d_ros) for catkin_python_setup(); do not run it
# directly.
from catkin_pkg.python_setup import generate_distutils_setup
from setuptools import setup

setup(**generate_distutils_setup(packages=['minibot3d_ros'], package_dir={'': 'src'}))
