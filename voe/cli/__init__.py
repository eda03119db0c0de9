"""The typer command-line interface. Thin: every command parses options and calls the library."""
