"""``python -m urdftool``."""

from urdftool.cli import main

main()
