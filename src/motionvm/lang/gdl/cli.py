"""What `motionvm check|run|dump` call for `.gdl` files (the top-level CLI imports this)."""

from motionvm.lang.gdl.driver import main_check, main_dump, main_run

__all__ = ["main_check", "main_dump", "main_run"]
