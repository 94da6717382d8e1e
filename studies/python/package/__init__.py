"""vrv installed by `pip install .` (setup.py): the pybind11 module is vrv/vrv.*.so, with the image
module and the plot script beside it; `import vrv` gives its names as the build tree's vrv.*.so
does (docs/library.md)."""
from .vrv import *  # noqa: F401,F403
from .vrv import __doc__  # noqa: F401
