"""Leases on what robots share (lift cars, doors, narrow corridors): granted with an expiry, so
a robot that stops answering never holds a resource for ever (DESIGN §9).

The lease book is plain bookkeeping on the caller's clock, below both users: a lone robot's
runtime lends itself its lift cars from one (:mod:`polynav.runtime.lift_sessions`), and the
fleet's master control grants the site's resources from one (:mod:`polynav.fleet`).
"""
