"""Models scored by surprise: the protocol, reference predictors, learned models, adapters."""
