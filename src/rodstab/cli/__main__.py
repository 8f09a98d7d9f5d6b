"""``python -m rodstab.cli``: the ``rodstab`` command."""

from .main import main

main()
