import sys

from tennislab.cli import main

sys.exit(main())
