"""Communication: the TCP servers and clients of the controller (Native and User ASCII,
Modbus TCP). They reach the machine through the language-neutral command layer
(`motion.commands`) and the `runtime` protocols, never through a language."""
