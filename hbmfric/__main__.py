"""``python -m hbmfric``: the ``hbmfric`` command (``hbmfric.cli``)."""

import sys

from hbmfric.cli import main

sys.exit(main())
