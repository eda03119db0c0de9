"""Reports: tables, figures, markdown and html, built from stored results only.

Never imports ``voe.sim``, ``voe.models`` or torch.
"""
