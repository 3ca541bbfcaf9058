"""The HMPL built-in functions, one module per chapter group of the manual."""
