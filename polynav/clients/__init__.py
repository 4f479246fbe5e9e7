"""Clients of the vendor dialects, so scripts written against a vendor's SDK run against
polynav (or a vendor's robot) with the same calls."""
