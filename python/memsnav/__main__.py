from memsnav.cli import main

raise SystemExit(main())
