"""VDA 5050 as the standard publishes it: its JSON schemas, and validation against them.

The schemas under ``schemas/<version>/`` are the official ones (VDA5050/VDA5050 on GitHub, tags
2.0.0 and 2.1.0), shipped verbatim with their MIT licence (``schemas/LICENSE.txt``). polynav's own
fleet messages (:mod:`polynav.fleet.messages`) carry a subset of VDA 5050 and are not checked
against these; the schemas are for what reaches polynav from, or leaves it for, other vendors'
vehicles and master controls.
"""
