    def {{ m.name }}(self{% for p in m.ins %}, {{ p }}{% endfor %}):
        """{{ m.krl }}: {{ m.summary }}
{% for l in m.doc %}
        {{ l }}
{%- endfor %}
        """
{%- block body %}{% endblock %}
