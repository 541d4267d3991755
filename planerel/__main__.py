"""``python -m planerel``: the ``planerel`` command (:func:`planerel.cli.main`)."""

import sys

from planerel.cli import main

if __name__ == "__main__":  # importing this module (a walk over the package) runs nothing
    sys.exit(main())
