"""``python -m pipeline.cli`` is the ``screen`` command."""

import sys

from .main import main

sys.exit(main())
