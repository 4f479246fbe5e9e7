"""VDA 5050 as the standard publishes it: its JSON schemas, and validation against them.

The schemas under ``schemas/<version>/`` are the official ones (VDA5050/VDA5050 on GitHub, tags
2.0.0 and 2.1.0), shipped verbatim with their MIT licence (``schemas/LICENSE.txt``). Every
message polynav's fleet and vehicles exchange on the standard's topics
(:mod:`polynav.fleet.messages`) is checked against them when it is written and when it is read
(:mod:`polynav.fleet.codec`).
"""
