"""Root-solver benchmark (same as `python -m max2code.conformance.bench`)."""
import sys

from max2code.conformance.bench import main

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
