"""The base of the objects that hold a handle of the library."""


class _Handle:
    """An object holding a handle of the library: it cannot be copied or pickled (two owners
    would free the handle twice, and a pointer means nothing in another process)."""
    __slots__ = ()

    def __reduce__(self):
        raise TypeError(f"a frix {type(self).__name__} cannot be copied or pickled "
                        "(it holds a handle of the library; copy the arrays you need)")


class _Closing(_Handle):
    """A handle freed by close(), which `with` calls at the block's end."""
    __slots__ = ()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
