"""Input and output: TOML and CSV readers with errors that name file, row and field; shipped data; whole-file
writes."""
