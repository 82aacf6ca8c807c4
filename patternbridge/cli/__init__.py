"""Command-line interface: ``patternbridge <command> ...`` (see ``docs/cli.md``)."""
