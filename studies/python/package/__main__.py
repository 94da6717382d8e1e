"""`vrv ARGS` (the command pip installs) and `python3 -m vrv ARGS`: the program installed in this
package beside the module, its image module and plot script (setup.py)."""
import os
import sys
from pathlib import Path


def main():
    program = Path(__file__).resolve().parent / "vrv"
    os.execv(program, ["vrv", *sys.argv[1:]])


if __name__ == "__main__":
    main()
