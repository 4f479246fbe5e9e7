"""The site's fleet layer (DESIGN §9): what several robots share, and the messages to them.

Robots never call each other. What they share (lift cars, doors, narrow corridors, chargers) is
granted here as a *lease* with an expiry (:mod:`polynav.leases.book`), so a robot that stops
answering never holds a lift for ever. The fleet talks to each robot only through messages in the
shape of VDA 5050 (orders and instant actions down, state up), over a transport that is in-process
today and MQTT later.
"""
