"""Readers and writers: probe sets, manifests, checksums, atomic writes."""
