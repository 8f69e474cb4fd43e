"""``python -m bench [--quick] [--json FILE] [--readme]``: the same as ``mura bench``."""

import sys

from agent.cli import main

sys.exit(main(["bench", *sys.argv[1:]]))
