"""Print the N-th shell command of README.md (fenced ```sh blocks, 1-based)."""

import re
import sys
from pathlib import Path

blocks = re.findall(r"```sh\n(.*?)```", Path("README.md").read_text(), flags=re.S)
print(blocks[int(sys.argv[1]) - 1].strip())
