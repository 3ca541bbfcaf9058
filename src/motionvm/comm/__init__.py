"""Communication: the TCP servers and clients of the controller (Native and User ASCII,
Modbus TCP; manual chapter 21). They reach the machine through the language-neutral
command layer (`motion.commands`) and the `runtime` protocols, never through a language.

    hub.py            where the network meets the cycle: work posted by server threads
                      runs in the simulation thread at a cycle boundary; the protocols
                      the upper layers implement (NativeTable, VariableTable, AsciiAgentPort)
    servers.py        the three servers on one asyncio loop in a background thread
    lineserver.py     the line transport of both ASCII servers (limits, floods, idle clients)
    gate.py           what an ASCII connection passes first: the refusal of HTTP, the token
    native.py         Native ASCII request lines and reply values
    modbus_server.py  pymodbus's server on our context; modbus_map.py the register map
    clients.py        the ASCII and Modbus TCP client operations, in error codes of 18.1.1
    config.py         the machine file's [comm] table (addresses, timeouts, access rules)
"""
