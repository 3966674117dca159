{% extends "py/mm/method.py" %}
{%- block body %}
{%- if m.has_bad %}
        if {{ m.bad }}:
            status = self.BAD_ARGUMENT
        else:
            status, _ = self._exchange({{ m.cmd }}, [{{ m.tx }}])
{%- else %}
        status, _ = self._exchange({{ m.cmd }}, [{{ m.tx }}])
{%- endif %}
        self.last_status = status
{%- if !m.ret.is_empty() %}
        return {{ m.ret }}
{%- endif %}
{%- endblock %}
