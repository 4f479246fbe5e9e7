"""Multi-map routing: routes across the site's maps through its lift and direct connections."""
