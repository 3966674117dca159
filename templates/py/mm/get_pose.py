{% extends "py/mm/method.py" %}
{%- block body %}
        p = self._point(serial, self.{{ m.kind }})
        if p is None:
            return {{ m.none_ret }}
        return {{ m.value }}(*p.values), p.label, p.speed
{%- endblock %}
