"""``python -m exdex <command>``: the same as the ``exdex`` console script."""
import sys

from exdex.cli import main

sys.exit(main())
