"""hmpl package."""
