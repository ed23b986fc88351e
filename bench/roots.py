"""Root-solver benchmark (same as `python -m max2code.conformance.bench`),
of this checkout's package and runtimes (as the other bench scripts)."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from max2code.conformance.bench import main  # noqa: E402

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
