"""``python -m pipeline`` is the ``screen`` command."""

import sys

from .cli import main

sys.exit(main())
