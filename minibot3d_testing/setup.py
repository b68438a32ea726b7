# Installs the test helper module (src/minibot3d_testing) for catkin_python_setup(); do not run it
# directly.
from catkin_pkg.python_setup import generate_distutils_setup
from setuptools import setup

setup(**generate_distutils_setup(packages=['minibot3d_testing'], package_dir={'': 'src'}))
