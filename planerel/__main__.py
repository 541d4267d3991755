"""``python -m planerel``: the ``planerel`` command (:func:`planerel.cli.main`)."""

import sys

from planerel.cli import main

sys.exit(main())
