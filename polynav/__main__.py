from polynav.cli import main

raise SystemExit(main())
