"""The languages. Each `lang/<name>/` holds a front end (preprocess, lex, parse, check,
lower to Python) and its run side, a client of the controller's cycle; the languages never
import each other. Modules directly in this folder would be shared by all of them."""
