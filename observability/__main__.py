"""``python -m observability``: the same as the ``observability`` command."""

import sys

from .cli import main

sys.exit(main())
