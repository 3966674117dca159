{% extends "py/mm/method.py" %}
{%- block body %}
        self.ip = None
        if {{ m.bad }}:
            self.last_status = self.BAD_ARGUMENT
        else:
            self.ip, self.port, self.connect_timeout = ip, int(port), float(time_out)
            self.last_status = 0
{%- endblock %}
