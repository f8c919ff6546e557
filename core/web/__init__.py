"""The register in a browser (``metro serve``): read-only pages for the lab, and the public page
that verifies a certificate by its number."""
