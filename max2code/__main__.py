from max2code.cli import main

raise SystemExit(main())
