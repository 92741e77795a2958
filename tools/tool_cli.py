"""What the project's Python tools share (tools/ab_bench.py, tools/ray_instructions.py): errors as
one line `TOOL: message` with exit code 2, as every frameless command gives them, and finding the
frameless binary they run."""
import argparse
import os
import shutil
import sys


class Failure(Exception):
    """An error the tool reports as its one line."""


def fail(tool, message):
    print(f"{tool}: {message}", file=sys.stderr)
    sys.exit(2)


class OneLineParser(argparse.ArgumentParser):
    """argparse whose errors (a bad flag, a missing argument) are the tool's one line too."""

    def __init__(self, tool, **kwargs):
        super().__init__(**kwargs)
        self.tool = tool

    def error(self, message):
        fail(self.tool, message)


def executable(binary):
    """The path of `binary` (a path, or a name on PATH), or None when it is no executable file."""
    found = shutil.which(binary)
    return found if found and not os.path.isdir(found) else None
