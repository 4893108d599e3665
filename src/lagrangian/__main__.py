"""``python -m lagrangian`` runs the command line."""

from lagrangian.cli.main import main

raise SystemExit(main())
