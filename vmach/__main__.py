from vmach.cli import main

raise SystemExit(main())
