import sys

from talkdem.cli import main

sys.exit(main())
