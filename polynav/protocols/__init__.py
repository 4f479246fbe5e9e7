"""Vendor protocol adapters, one package per dialect (STYLE R4)."""
